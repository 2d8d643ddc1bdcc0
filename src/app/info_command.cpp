// `veil info <file>`: what a scene (.json) or OpenVDB (.vdb) file holds.
#include "app/commands.h"

#include "vdb/vdb_info.h"

#include "base/error.h"
#include "base/text.h"
#include "scene/scene.h"

#include <iostream>
#include <memory>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

const char* lightTypeName(scene::LightType t) {
    switch (t) {
    case scene::LightType::Directional:
        return "directional";
    case scene::LightType::Spot:
        return "spot";
    case scene::LightType::Point:
        return "point";
    }
    return "?";
}

void printScene(const fs::path& path) {
    const scene::Scene s = scene::loadScene(path);
    std::size_t triangles = 0;
    for (const auto& o : s.objects)
        triangles += s.meshes.at(o.mesh).triangleCount();
    std::size_t transparent = 0;
    for (const auto& o : s.objects)
        transparent += s.materials.at(o.material).isTransparent();
    glm::vec3 lo, hi;
    s.bounds(lo, hi);
    std::cout << "scene " << path.string() << "\n"
              << "  render     " << s.render.width << "x" << s.render.height << ", oit "
              << s.render.oit << ", tonemap " << s.render.tonemap << ", seed " << s.render.seed
              << "\n"
              << "  objects    " << s.objects.size() << " (" << transparent << " transparent), "
              << triangles << " triangles, " << s.materials.size() << " materials\n"
              << fmt::format("  bounds     ({:.3g}, {:.3g}, {:.3g}) .. ({:.3g}, {:.3g}, {:.3g})\n",
                             lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    for (const auto& c : s.cameras)
        std::cout << "  camera     " << c.name << " ("
                  << (c.type == scene::CameraType::Perspective ? "perspective" : "orthographic")
                  << ")\n";
    for (const auto& l : s.lights)
        std::cout << "  light      " << (l.name.empty() ? "-" : l.name) << " ("
                  << lightTypeName(l.type) << ", intensity " << l.intensity
                  << (l.castShadows ? ", shadows" : "") << ")\n";
    for (const auto& v : s.volumes)
        std::cout << "  volume     " << v.path.string() << " grid '" << v.grid << "'\n";
}

std::string formatBytes(std::size_t bytes) {
    if (bytes >= (std::size_t(1) << 20)) return fmt::format("{:.2f} MiB", bytes / 1048576.0);
    return fmt::format("{:.1f} KiB", bytes / 1024.0);
}

// Like `vdb_print -l`: per grid its index and name, type and class, active voxels, value
// range, bounds, voxel size, memory, and every metadata entry. `selector` (a name or an
// index, vdb/grid_select.h) prints one grid only.
void printVdb(const fs::path& path, const std::string& selector) {
    const vdb::FileInfo file = vdb::describeVdbFile(path, selector);
    std::cout << "vdb " << path.string() << ": " << file.gridCount << " grid(s)\n";
    for (const vdb::GridInfo& g : file.grids) {
        std::cout << fmt::format(
            "  {} '{}' {} ({}): {} active voxels, {}, index bounds [{} {} {}]..[{} {} {}], voxel "
            "size ({:.4g} {:.4g} {:.4g}), world bounds ({:.4g} {:.4g} {:.4g})..({:.4g} {:.4g} "
            "{:.4g}), transform {}",
            g.index, g.name, g.type, g.gridClass, g.activeVoxels, g.valueRange, g.indexMin[0],
            g.indexMin[1], g.indexMin[2], g.indexMax[0], g.indexMax[1], g.indexMax[2],
            g.voxelSize[0], g.voxelSize[1], g.voxelSize[2], g.worldMin[0], g.worldMin[1],
            g.worldMin[2], g.worldMax[0], g.worldMax[1], g.worldMax[2], g.transform);
        // What `veil render` would upload: brick atlas or dense texture (src/volume).
        if (g.gridBytes > 0)
            std::cout << ", grid " << formatBytes(g.gridBytes) << ", GPU "
                      << formatBytes(g.gpuBytes);
        std::cout << "\n";
        for (const auto& m : g.metadata)
            std::cout << fmt::format("      {}: {} = {}\n", m.name, m.type, m.value);
    }
}

} // namespace

void addInfoCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    auto grid = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("info", "Print what a scene (.json) or .vdb file holds");
    cmd->add_option("file", *file, "A scene file (.json) or an OpenVDB file (.vdb)")->required();
    cmd->add_option("--grid", *grid, ".vdb: only this grid (name or index)");
    cmd->callback([file, grid] {
        const fs::path path(*file);
        // OpenVDB would block on a FIFO and read /dev/zero forever.
        std::error_code ec;
        const fs::file_status st = fs::status(path, ec);
        VEIL_CHECK(!fs::exists(st) || fs::is_regular_file(st),
                   "cannot read '{}': not a regular file", *file);
        if (lowerExtension(*file) == ".vdb")
            printVdb(path, *grid);
        else {
            VEIL_CHECK(grid->empty(), "--grid is for .vdb files, not '{}'", *file);
            printScene(path);
        }
    });
}

} // namespace veil::app
