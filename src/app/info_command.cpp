// `veil info <file>`: what a scene (.json) or OpenVDB (.vdb) file holds.
#include "app/commands.h"

#include "base/error.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <iostream>
#include <memory>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

const char* lightTypeName(scene::LightType t) {
    switch (t) {
    case scene::LightType::Directional: return "directional";
    case scene::LightType::Spot: return "spot";
    case scene::LightType::Point: return "point";
    }
    return "?";
}

void printScene(const fs::path& path) {
    const scene::Scene s = scene::loadScene(path);
    std::size_t triangles = 0;
    for (const auto& o : s.objects) triangles += s.meshes.at(o.mesh).triangleCount();
    std::size_t transparent = 0;
    for (const auto& o : s.objects) transparent += s.materials.at(o.material).isTransparent();
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

void printVdb(const fs::path& path) {
    openvdb::initialize();
    VEIL_CHECK(fs::exists(path), "cannot open '{}': no such file", path.string());
    openvdb::GridPtrVecPtr grids;
    openvdb::io::File file(path.string());
    try {
        file.open();
        grids = file.getGrids();
        file.close();
    } catch (const openvdb::Exception& e) {
        throw Error(fmt::format("cannot read OpenVDB file '{}': {}", path.string(), e.what()));
    }
    std::cout << "vdb " << path.string() << ": " << grids->size() << " grid(s)\n";
    for (const auto& grid : *grids) {
        const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
        const openvdb::Vec3d vs = grid->voxelSize();
        const auto wlo = grid->indexToWorld(box.min().asVec3d());
        const auto whi = grid->indexToWorld(box.max().asVec3d());
        std::cout << fmt::format(
            "  '{}' {} ({}): {} active voxels, index bounds [{} {} {}]..[{} {} {}], voxel size "
            "({:.4g} {:.4g} {:.4g}), world bounds ({:.4g} {:.4g} {:.4g})..({:.4g} {:.4g} {:.4g})\n",
            grid->getName(), grid->valueType(),
            openvdb::GridBase::gridClassToString(grid->getGridClass()), grid->activeVoxelCount(),
            box.min().x(), box.min().y(), box.min().z(), box.max().x(), box.max().y(),
            box.max().z(), vs.x(), vs.y(), vs.z(), wlo.x(), wlo.y(), wlo.z(), whi.x(), whi.y(),
            whi.z());
    }
}

} // namespace

void addInfoCommand(CLI::App& app) {
    auto file = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("info", "Print what a scene (.json) or .vdb file holds");
    cmd->add_option("file", *file, "A scene file (.json) or an OpenVDB file (.vdb)")->required();
    cmd->callback([file] {
        const fs::path path(*file);
        if (path.extension() == ".vdb")
            printVdb(path);
        else
            printScene(path);
    });
}

} // namespace veil::app
