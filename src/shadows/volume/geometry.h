// The `volume` shadow technique's geometry on the GPU (src/shadows/volume/volume.cpp draws it):
// every opaque object's welded vertices, transformed into world space once per frame
// (transform.comp), the depth pre-pass's triangles over them (one glDrawElements, no geometry
// shader), and the opaque casters' edge adjacency in world vertex indices with one triangle
// range per caster (silhouette.comp reads it; compact.comp skips the culled casters' ranges).
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace veil::shadows {

struct VolumeGeometry {
    gpu::Buffer source{gpu::NoCreate}, models{gpu::NoCreate}, world{gpu::NoCreate},
        prepassIndices{gpu::NoCreate}, adjacency{gpu::NoCreate}, ranges{gpu::NoCreate};
    gpu::VertexArray prepassVao{gpu::NoCreate};
    std::vector<int> modelObjects; // the object of each models[] entry (opaque, with triangles)
    std::vector<glm::vec3> meshLo, meshHi;      // object-space bounds per scene mesh
    std::vector<std::uint32_t> casterTriangles; // per caster (the casters' order)
    std::vector<bool> casterClosed;
    GLsizei prepassIndexCount = 0;
    int vertexCount = 0;
    std::uint64_t totalCasterTriangles = 0;

    std::size_t gpuBytes() const {
        return source.size() + models.size() + world.size() + prepassIndices.size() +
               adjacency.size() + ranges.size();
    }
};

// Builds the geometry of `scene`'s opaque objects and of `casters` (object indices: opaque,
// casting shadows). Refuses particle casters with one line naming the scene and the object;
// warns once per caster mesh that is not a closed 2-manifold (per-triangle prisms).
VolumeGeometry buildVolumeGeometry(const scene::Scene& scene, const std::vector<int>& casters);

// Uploads the model matrices and runs transform.comp (the world vertices of this frame).
void updateVolumeGeometry(const scene::Scene& scene, VolumeGeometry& geometry,
                          const gpu::Program& transform);

} // namespace veil::shadows
