#include "voxelize/triangles.h"

#include "base/error.h"

namespace veil::voxelize {

void Triangles::bounds(glm::vec3& lo, glm::vec3& hi) const {
    VEIL_CHECK(!vertices.empty(), "nothing to voxelize: the scene has no triangles");
    lo = hi = vertices[0];
    for (const glm::vec3& v : vertices) {
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
