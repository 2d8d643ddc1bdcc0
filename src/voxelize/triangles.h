// World-space triangle soups: what every voxelizer consumes (3 vertices per triangle).
#pragma once

#include "scene/mesh.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <vector>

namespace veil::voxelize {

struct Triangles {
    std::vector<glm::vec3> vertices; // 3 per triangle, world space
    std::size_t count() const { return vertices.size() / 3; }
    void bounds(glm::vec3& lo, glm::vec3& hi) const; // throws if empty
    void append(const scene::MeshData& mesh, const glm::mat4& transform);
};

// Every object of the scene (billboard meshes are skipped: they have no surface).
Triangles flattenScene(const scene::Scene& scene);
Triangles fromMesh(const scene::MeshData& mesh, const glm::mat4& transform = glm::mat4(1.0f));

} // namespace veil::voxelize
