#include "voxelize/grid_fit.h"

#include "base/error.h"
#include "base/text.h"
#include "scene/mesh_file_check.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace veil::voxelize {

namespace fs = std::filesystem;

namespace {
constexpr double kMinMeshVoxel = 2e-5; // OpenVDB: scale determinant >= 3e-15, voxel >= 1.44e-5
} // namespace

bool isMeshFile(const std::string& path) {
    const std::string ext = lowerExtension(path);
    return ext == ".obj" || ext == ".ply" || ext == ".glb" || ext == ".gltf";
}

// A scene of one object: the mesh file, with its own materials.
scene::Scene sceneForMesh(const fs::path& mesh) {
    std::error_code ec;
    VEIL_CHECK(fs::is_regular_file(mesh, ec), "cannot read mesh '{}': no such file", mesh.string());
    // The camera is required by the scene format; the orthographic grid does not use it.
    const nlohmann::json doc = {{"cameras", {{{"name", "mesh"}, {"position", {0, 0, 1}}}}},
                                {"objects", {{{"mesh", fs::absolute(mesh).string()}}}}};
    scene::Scene scene;
    try {
        scene = scene::parseScene(doc, fs::absolute(mesh).parent_path());
    } catch (const Error& e) {
        const std::string what = e.what();
        if (what.find(mesh.filename().string()) != std::string::npos) throw;
        throw Error(fmt::format("mesh '{}': {}", mesh.string(), what));
    }
    // A mesh collapsed to one point (a glTF node scaled by 0) has no grid to fit.
    glm::vec3 lo, hi;
    scene.bounds(lo, hi);
    if (glm::all(glm::equal(lo, hi))) {
        std::string nodes;
        const std::string ext = lowerExtension(mesh.string());
        if (ext == ".gltf" || ext == ".glb")
            for (const std::string& n : scene::gltfCollapsingNodes(mesh))
                nodes += (nodes.empty() ? "; collapsed by " : ", ") + n;
        throw Error(fmt::format("mesh '{}': every vertex lies at ({:g} {:g} {:g}), so it has no "
                                "extent to voxelize{}",
                                mesh.string(), lo.x, lo.y, lo.z, nodes));
    }
    return scene;
}

SliceMap fitGrid(const scene::Scene& scene, const Triangles& tris, const GridRequest& request,
                 bool mesh) {
    glm::vec3 lo, hi;
    tris.bounds(lo, hi);
    int slices = request.slices > 0 ? request.slices : request.res;
    SliceMap grid;
    if (request.perspective) {
        const scene::Camera& cam = scene.camera(request.camera);
        // Near/far fitted to the scene bounds along the view axis (with a 2% margin).
        const glm::dvec3 eye(cam.position), dir = glm::normalize(glm::dvec3(cam.target) - eye);
        double dmin = 1e300, dmax = -1e300;
        for (int i = 0; i < 8; ++i) {
            const glm::dvec3 c(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
            dmin = std::min(dmin, glm::dot(c - eye, dir));
            dmax = std::max(dmax, glm::dot(c - eye, dir));
        }
        const double n = std::max(dmin * 0.98, 1e-3 * dmax), f = dmax * 1.02;
        VEIL_CHECK(f > n && dmax > 0.0, "the scene lies behind camera '{}'", cam.name);
        grid = makePerspectiveGrid(eye, glm::dvec3(cam.target), glm::dvec3(cam.up), cam.fovYDegrees,
                                   n, f, request.res, request.res, slices);
    } else if (mesh) {
        // Cubic voxels: --res cells along the largest extent (with a 3% margin per side), as
        // many as the bounds need along the others; --slices overrides the z count.
        const glm::dvec3 e = glm::dvec3(hi - lo), c = 0.5 * glm::dvec3(lo + hi);
        const double voxel = std::max({e.x, e.y, e.z, 1e-9}) * 1.06 / request.res;
        // OpenVDB refuses scale maps of determinant below 3e-15 (voxels under 1.4e-5).
        VEIL_CHECK(voxel >= kMinMeshVoxel,
                   "the mesh spans {:.3g} x {:.3g} x {:.3g}: at --res {} its voxels ({:.3g}) are "
                   "below the {:g} that OpenVDB stores (scale the mesh up or lower --res)",
                   e.x, e.y, e.z, request.res, voxel, kMinMeshVoxel);
        glm::ivec3 dims;
        for (int i = 0; i < 3; ++i)
            dims[i] =
                std::clamp(static_cast<int>(std::ceil(e[i] * 1.06 / voxel - 1e-9)), 1, request.res);
        glm::dvec3 h = 0.5 * voxel * glm::dvec3(dims);
        if (request.slices > 0) { // z fitted to the bounds, cut into the slices asked for
            dims.z = request.slices;
            h.z = 0.5 * std::max(e.z * 1.06, voxel);
        }
        slices = dims.z;
        grid = makeOrthoGrid(c - h, c + h, dims.x, dims.y, slices);
    } else {
        // Orthographic along +z world, fitted to the bounds with a 3% margin.
        const glm::dvec3 e = glm::dvec3(hi - lo), c = 0.5 * glm::dvec3(lo + hi);
        const glm::dvec3 half = 0.5 * glm::max(e, glm::dvec3(1e-6 * glm::length(e))) * 1.06;
        grid = makeOrthoGrid(c - half, c + half, request.res, request.res, slices);
    }
    return grid;
}

} // namespace veil::voxelize
