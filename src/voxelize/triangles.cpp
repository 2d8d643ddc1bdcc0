#include "voxelize/triangles.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>

namespace veil::voxelize {

void Triangles::bounds(glm::vec3& lo, glm::vec3& hi) const {
    VEIL_CHECK(!vertices.empty(), "nothing to voxelize: the scene has no triangles");
    lo = hi = vertices[0];
    for (const glm::vec3& v : vertices) {
        // Transforms can carry a vertex past what float grid fitting handles (extents and
        // their squares must stay finite).
        VEIL_CHECK(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) &&
                       std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}) <=
                           scene::kMaxMeshCoordinate,
                   "a triangle vertex at ({} {} {}) lies beyond {:g} (after its object's "
                   "transform): too far out to voxelize in float",
                   v.x, v.y, v.z, scene::kMaxMeshCoordinate);
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
}

void Triangles::append(const scene::MeshData& mesh, const glm::mat4& transform) {
    if (mesh.billboard) return;
    vertices.reserve(vertices.size() + mesh.indices.size());
    for (std::uint32_t i : mesh.indices) {
        VEIL_CHECK(i < mesh.positions.size(), "mesh '{}' has index {} past its {} vertices",
                   mesh.name, i, mesh.positions.size());
        vertices.push_back(glm::vec3(transform * glm::vec4(mesh.positions[i], 1.0f)));
    }
}

Triangles flattenScene(const scene::Scene& scene) {
    Triangles t;
    for (const scene::Object& o : scene.objects)
        t.append(scene.meshes.at(o.mesh), o.transform);
    return t;
}

Triangles fromMesh(const scene::MeshData& mesh, const glm::mat4& transform) {
    Triangles t;
    t.append(mesh, transform);
    return t;
}

} // namespace veil::voxelize
