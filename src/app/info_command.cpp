// `veil info <file>`: what a scene (.json) or OpenVDB (.vdb) file holds.
#include "app/commands.h"

#include "vdb/grid_select.h"

#include "base/error.h"
#include "base/text.h"
#include "scene/scene.h"
#include "volume/density_grid.h"
#include "volume/gpu_volume.h"
#include "volume/vdb_file.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Count.h>

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
    for (const auto& v : s.volumes) {
        const std::string name = v.name.empty() ? "-" : v.name;
        const std::string optics =
            fmt::format("density_scale {:.4g}, albedo ({:.3g} {:.3g} {:.3g}), g {:.3g}",
                        v.densityScale, v.albedo.x, v.albedo.y, v.albedo.z, v.anisotropy);
        if (v.procedural == "homogeneous")
            std::cout << "  volume     " << name << " (homogeneous haze filling the scene, "
                      << optics << ")\n";
        else if (!v.procedural.empty())
            std::cout << "  volume     " << name << " (procedural " << v.procedural << ", size "
                      << fmt::format("{:.4g} {:.4g} {:.4g}", v.size.x, v.size.y, v.size.z) << ", "
                      << optics << ")\n";
        else
            std::cout << "  volume     " << name << " (" << v.path.string() << " grid '" << v.grid
                      << "', " << optics << ")\n";
    }
}

std::string formatBytes(std::size_t bytes) {
    if (bytes >= (std::size_t(1) << 20)) return fmt::format("{:.2f} MiB", bytes / 1048576.0);
    return fmt::format("{:.1f} KiB", bytes / 1024.0);
}

// "min 0, max 5.71" over the active values (vectors: their lengths); empty for other types.
template <typename GridT>
std::string valueRange(const openvdb::GridBase& base) {
    const auto& grid = static_cast<const GridT&>(base);
    if (grid.activeVoxelCount() == 0) return "no active values";
    if constexpr (openvdb::VecTraits<typename GridT::ValueType>::IsVec) {
        double lo = 1e300, hi = -1e300;
        for (auto it = grid.cbeginValueOn(); it; ++it) {
            const double l = it->length();
            lo = std::min(lo, l);
            hi = std::max(hi, l);
        }
        return fmt::format("|value| min {:.6g}, max {:.6g}", lo, hi);
    } else {
        const auto mm = openvdb::tools::minMax(grid.tree());
        return fmt::format("min {:.6g}, max {:.6g}", double(mm.min()), double(mm.max()));
    }
}

std::string valueRangeOf(const openvdb::GridBase& g) {
    if (g.isType<openvdb::FloatGrid>()) return valueRange<openvdb::FloatGrid>(g);
    if (g.isType<openvdb::DoubleGrid>()) return valueRange<openvdb::DoubleGrid>(g);
    if (g.isType<openvdb::Int32Grid>()) return valueRange<openvdb::Int32Grid>(g);
    if (g.isType<openvdb::Int64Grid>()) return valueRange<openvdb::Int64Grid>(g);
    if (g.isType<openvdb::Vec3SGrid>()) return valueRange<openvdb::Vec3SGrid>(g);
    if (g.isType<openvdb::Vec3DGrid>()) return valueRange<openvdb::Vec3DGrid>(g);
    return "min/max n/a for " + g.valueType();
}

// Like `vdb_print -l`: per grid its index and name, type and class, active voxels, value
// range, bounds, voxel size, memory, and every metadata entry. `selector` (a name or an
// index, vdb/grid_select.h) prints one grid only.
void printVdb(const fs::path& path, const std::string& selector) {
    const openvdb::GridPtrVecPtr grids = volume::readVdbFile(path);
    std::vector<std::size_t> which;
    if (selector.empty()) {
        for (std::size_t i = 0; i < grids->size(); ++i)
            which.push_back(i);
    } else {
        which.push_back(
            vdb::selectGrid(
                *grids, path, selector, [](const openvdb::GridBase&) { return true; }, "a grid")
                .index);
    }
    std::cout << "vdb " << path.string() << ": " << grids->size() << " grid(s)\n";
    for (std::size_t i : which) {
        const openvdb::GridBase& g = *(*grids)[i];
        const openvdb::CoordBBox box = g.evalActiveVoxelBoundingBox();
        const openvdb::Vec3d vs = g.voxelSize();
        const openvdb::BBoxd world = g.transform().indexToWorld(box);
        std::cout << fmt::format(
            "  {} '{}' {} ({}): {} active voxels, {}, index bounds [{} {} {}]..[{} {} {}], voxel "
            "size ({:.4g} {:.4g} {:.4g}), world bounds ({:.4g} {:.4g} {:.4g})..({:.4g} {:.4g} "
            "{:.4g}), transform {}",
            i, g.getName(), g.valueType(), openvdb::GridBase::gridClassToString(g.getGridClass()),
            g.activeVoxelCount(), valueRangeOf(g), box.min().x(), box.min().y(), box.min().z(),
            box.max().x(), box.max().y(), box.max().z(), vs.x(), vs.y(), vs.z(), world.min().x(),
            world.min().y(), world.min().z(), world.max().x(), world.max().y(), world.max().z(),
            g.transform().mapType());
        if (g.isType<openvdb::FloatGrid>() && g.activeVoxelCount() > 0) {
            // What `veil render` would upload: brick atlas or dense texture (src/volume).
            const auto& grid = static_cast<const openvdb::FloatGrid&>(g);
            std::cout << ", grid " << formatBytes(grid.memUsage()) << ", GPU "
                      << formatBytes(volume::estimateGpuBytes(grid, {}));
        }
        std::cout << "\n";
        for (auto m = g.beginMeta(); m != g.endMeta(); ++m)
            std::cout << fmt::format("      {}: {} = {}\n", m->first, m->second->typeName(),
                                     printable(m->second->str(), 200));
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
