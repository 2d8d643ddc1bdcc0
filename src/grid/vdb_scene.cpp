#include "grid/vdb_scene.h"

#include "grid/grid_select.h"
#include "grid/optical_depth.h"

#include "base/error.h"
#include "grid/vdb_file.h"

#include <openvdb/tools/Count.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>

namespace veil::vdb {

namespace fs = std::filesystem;

namespace {
constexpr double kMedianOpticalDepth = 1.5;
constexpr double kFill = 0.9; // of the smaller image side, by the box's nearest projection
} // namespace

BoxFraming frameBox(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& towardEye,
                    double fovY, double fill) {
    // The camera's axes as scene::Camera builds them (up +y): z toward the eye.
    const glm::dvec3 z = glm::normalize(towardEye);
    glm::dvec3 x = glm::cross(glm::dvec3(0, 1, 0), z);
    x = glm::length(x) > 1e-9 ? glm::normalize(x) : glm::dvec3(1, 0, 0);
    const glm::dvec3 y = glm::cross(z, x);
    const double slope = std::tan(fovY * 0.5 * M_PI / 180.0) * fill;
    std::array<glm::dvec3, 8> corners;
    for (int i = 0; i < 8; ++i)
        corners[i] = glm::dvec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    BoxFraming f;
    f.target = 0.5 * (lo + hi);
    // A corner q (relative to the target) projects inside the fraction `fill` of the view when
    // max(|q.x|, |q.y|) / (d - q.z) <= slope, so d >= q.z + max(|q.x|, |q.y|) / slope. In
    // perspective the box's projection is not centred on its centre's: the target moves by the
    // projected bounds' middle, a few times (it converges in two or three).
    for (int pass = 0; pass < 5; ++pass) {
        f.distance = 1e-6;
        for (const glm::dvec3& c : corners) {
            const glm::dvec3 q = c - f.target;
            f.distance = std::max(f.distance, glm::dot(q, z) + std::max(std::abs(glm::dot(q, x)),
                                                                        std::abs(glm::dot(q, y))) /
                                                                   slope);
        }
        if (pass == 4) break;
        glm::dvec2 lower(1e300), upper(-1e300);
        for (const glm::dvec3& c : corners) {
            const glm::dvec3 q = c - f.target;
            const glm::dvec2 p =
                glm::dvec2(glm::dot(q, x), glm::dot(q, y)) / (f.distance - glm::dot(q, z));
            lower = glm::min(lower, p), upper = glm::max(upper, p);
        }
        const glm::dvec2 middle = 0.5 * (lower + upper) * f.distance;
        f.target += x * middle.x + y * middle.y;
    }
    f.nearest = 1e300, f.farthest = 0.0;
    for (const glm::dvec3& c : corners) {
        const double depth = f.distance - glm::dot(c - f.target, z);
        f.nearest = std::min(f.nearest, depth), f.farthest = std::max(f.farthest, depth);
    }
    return f;
}

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
    const openvdb::Vec3d extent = world.extents();
    const double radius = std::max(0.5 * extent.length(), 1e-6);
    const double fov = 40.0;
    openvdb::Vec3d dir(0.3, 0.35, 1.0);
    dir.normalize();
    const glm::dvec3 toward(dir.x(), dir.y(), dir.z());
    const BoxFraming framing =
        frameBox(glm::dvec3(world.min().x(), world.min().y(), world.min().z()),
                 glm::dvec3(world.max().x(), world.max().y(), world.max().z()), toward, fov, kFill);
    const glm::dvec3 target = framing.target, eye = target + toward * framing.distance;
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
           {"position", {eye.x, eye.y, eye.z}},
           {"target", {target.x, target.y, target.z}},
           {"fov_y", fov},
           {"near", std::max(0.9 * framing.nearest, 1e-3 * framing.distance)},
           {"far", framing.farthest + 0.5 * radius}}}},
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
