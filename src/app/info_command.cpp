// `veil info <file>`: what a scene (.json) or OpenVDB (.vdb) file holds.
#include "app/commands.h"

#include "base/error.h"
#include "base/text.h"
#include "scene/scene.h"
#include "volume/density_grid.h"
#include "volume/gpu_volume.h"

#include <openvdb/openvdb.h>

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

void printVdb(const fs::path& path) {
    const std::vector<volume::GridSummary> grids = volume::listGrids(path);
    std::cout << "vdb " << path.string() << ": " << grids.size() << " grid(s)\n";
    for (const auto& g : grids) {
        const openvdb::CoordBBox& box = g.indexBounds;
        std::cout << fmt::format(
            "  '{}' {} ({}): {} active voxels, index bounds [{} {} {}]..[{} {} {}], voxel size "
            "({:.4g} {:.4g} {:.4g}), world bounds ({:.4g} {:.4g} {:.4g})..({:.4g} {:.4g} {:.4g})",
            g.name, g.type, g.gridClass, g.activeVoxels, box.min().x(), box.min().y(),
            box.min().z(), box.max().x(), box.max().y(), box.max().z(), g.voxelSize.x(),
            g.voxelSize.y(), g.voxelSize.z(), g.worldBounds.min().x(), g.worldBounds.min().y(),
            g.worldBounds.min().z(), g.worldBounds.max().x(), g.worldBounds.max().y(),
            g.worldBounds.max().z());
        if (g.type == "float" && g.activeVoxels > 0) {
            // What `veil render` would upload: brick atlas or dense texture (src/volume).
            const auto grid = volume::loadDensityGrid(path, g.name);
            std::cout << ", grid " << formatBytes(grid->memUsage()) << ", GPU "
                      << formatBytes(volume::estimateGpuBytes(*grid, {}));
        }
        std::cout << "\n";
    }
}

} // namespace

void addInfoCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("info", "Print what a scene (.json) or .vdb file holds");
    cmd->add_option("file", *file, "A scene file (.json) or an OpenVDB file (.vdb)")->required();
    cmd->callback([file] {
        const fs::path path(*file);
        // OpenVDB would block on a FIFO and read /dev/zero forever.
        std::error_code ec;
        const fs::file_status st = fs::status(path, ec);
        VEIL_CHECK(!fs::exists(st) || fs::is_regular_file(st),
                   "cannot read '{}': not a regular file", *file);
        if (lowerExtension(*file) == ".vdb")
            printVdb(path);
        else
            printScene(path);
    });
}

} // namespace veil::app
