#include "grid/vdb_scene.h"

#include "grid/grid_select.h"
#include "grid/optical_depth.h"

#include "base/error.h"
#include "grid/vdb_file.h"

#include <openvdb/tools/Count.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace veil::vdb {

namespace fs = std::filesystem;

namespace {
constexpr double kMedianOpticalDepth = 1.5;
} // namespace

VdbScene sceneForVdb(const fs::path& vdb, const std::string& selector,
                     const std::vector<std::string>& overrides,
                     const scene::TechniqueChoice& choice) {
    const openvdb::GridPtrVecPtr grids = volume::readVdbFile(vdb);
    const SelectedGrid sel = selectGrid(
        *grids, vdb, selector,
        [](const openvdb::GridBase& g) { return g.isType<openvdb::FloatGrid>(); },
        "a float (density) grid");
    const auto& grid = static_cast<const openvdb::FloatGrid&>(*sel.grid);
    // The scene names volumes by grid name and loads the first of that name.
    for (std::size_t i = 0; i < sel.index; ++i)
        VEIL_CHECK((*grids)[i]->getName() != grid.getName(),
                   "'{}': grid {} shares its name '{}' with grid {}, and volumes are loaded by "
                   "name (the first one)",
                   vdb.string(), sel.index, grid.getName(), i);
    VEIL_CHECK(grid.activeVoxelCount() > 0, "'{}': grid {} '{}' has no active voxels", vdb.string(),
               sel.index, grid.getName());

    // World bounds of the active voxels (cell extents: index box grown by half a voxel).
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    const openvdb::BBoxd world = grid.transform().indexToWorld(
        openvdb::BBoxd(box.min().asVec3d() - 0.5, box.max().asVec3d() + 0.5));
    const openvdb::Vec3d center = world.getCenter(), extent = world.extents();
    const double radius = std::max(0.5 * extent.length(), 1e-6);
    const double fov = 40.0;
    // The bounding sphere fills 90% of the view's height (the smaller side at the default
    // square size): distance = r / sin(fov / 2) / 0.9.
    const double distance = radius / std::sin(fov * 0.5 * M_PI / 180.0) / 0.9;
    openvdb::Vec3d dir(0.3, 0.35, 1.0);
    dir.normalize();
    const openvdb::Vec3d eye = center + dir * distance;
    // The largest finite density: NaN or infinite voxels (set to 0 when the grid is loaded)
    // must not make the default density_scale NaN or 0.
    double maxDensity = 1e-6;
    for (auto it = grid.cbeginValueOn(); it; ++it)
        if (std::isfinite(*it)) maxDensity = std::max(maxDensity, double(*it));
    // The median optical depth of the lines of sight through the density becomes
    // kMedianOpticalDepth: thin parts stay visible, dense cores keep their shape.
    const OpticalDepthStats depth = medianOpticalDepth(grid, -dir);
    const double largest = std::max({extent.x(), extent.y(), extent.z(), 1e-6});
    const bool fromData = depth.median > 0.0;
    const double densityScale =
        fromData ? kMedianOpticalDepth / depth.median : 6.0 / (maxDensity * largest);

    nlohmann::json doc = {
        {"render",
         {{"width", 512}, {"height", 512}, {"background", {0.02, 0.02, 0.03}}, {"ambient", 0.1}}},
        {"cameras",
         {{{"name", "vdb"},
           {"position", {eye.x(), eye.y(), eye.z()}},
           {"target", {center.x(), center.y(), center.z()}},
           {"fov_y", fov},
           {"near", std::max(distance - 1.5 * radius, 1e-3 * distance)},
           {"far", distance + 1.5 * radius}}}},
        {"lights",
         {{{"type", "directional"}, {"direction", {-0.4, -1.0, -0.3}}, {"intensity", 3}}}},
        {"volumes",
         {{{"path", fs::absolute(vdb).string()},
           // A grid without a name is still the one selected (by index); the scene format
           // refuses an empty name, so it is set after parsing.
           {"grid", grid.getName().empty() ? std::string("density") : grid.getName()},
           {"density_scale", densityScale},
           {"albedo", 0.9}}}}};
    scene::applyTechniqueChoice(doc, choice);
    scene::applyOverrides(doc, overrides);
    VdbScene out;
    try {
        out.scene = scene::parseScene(doc, fs::absolute(vdb).parent_path());
    } catch (const Error& e) {
        throw Error(fmt::format("{} (default scene of '{}')", e.what(), vdb.string()));
    }
    out.scene.sourcePath = vdb;
    if (grid.getName().empty() && out.scene.volumes.at(0).grid == "density")
        out.scene.volumes.at(0).grid.clear();
    out.gridName = grid.getName();
    out.gridIndex = sel.index;
    // What is rendered, after --set: the camera and scale may have been overridden.
    const scene::Camera& cam = out.scene.cameras.front();
    const double used =
        out.scene.volumes.empty() ? densityScale : out.scene.volumes.front().densityScale;
    const std::string scaleNote =
        used != float(densityScale)
            ? fmt::format("set by --set; the default is {:.4g}", densityScale)
        : fromData ? fmt::format("median optical depth {:.3g} along the view", kMedianOpticalDepth)
                   : std::string("6 / (max density x largest extent): no line of sight meets "
                                 "density");
    out.description = fmt::format(
        "grid {} '{}' (float, {} active voxels, max {:.4g}) of {}; camera '{}' at "
        "({:.4g}, {:.4g}, {:.4g}) looking at ({:.4g}, {:.4g}, {:.4g}), density_scale {:.4g} "
        "({}; --set volumes.0.density_scale=X to change)",
        sel.index, grid.getName(), grid.activeVoxelCount(), maxDensity, vdb.string(), cam.name,
        cam.position.x, cam.position.y, cam.position.z, cam.target.x, cam.target.y, cam.target.z,
        used, scaleNote);
    return out;
}

} // namespace veil::vdb
