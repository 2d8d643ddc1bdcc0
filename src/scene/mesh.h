// Triangle meshes on the CPU: procedural shapes and files loaded through assimp.
#pragma once

#include "scene/material.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace veil::scene {

// Indexed triangle mesh in object space. For billboard meshes (quad-particle clouds) each
// particle is 4 vertices sharing its centre in `positions`; `uvs` hold the corner in
// [-1,1]^2 and `billboardSize` the half-extent in world units; the vertex shader expands the
// quad toward the camera. normals are still filled (+z) so every mesh has every attribute.
struct MeshData {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> uvs;
    std::vector<float> billboardSize; // empty unless billboard
    std::vector<std::uint32_t> indices;
    bool billboard = false;

    std::size_t triangleCount() const { return indices.size() / 3; }
    // Object-space bounds; billboard bounds include the particle size.
    void bounds(glm::vec3& lo, glm::vec3& hi) const;
};

// Procedural shapes (all centred at the origin, y up, outward normals, CCW front faces).
MeshData makePlane(glm::vec2 size, int subdivisions = 1); // in the xz plane, normal +y
MeshData makeBox(glm::vec3 size);                         // 24 vertices, flat normals
MeshData makeSphere(float radius, int segments = 48, int rings = 24);
MeshData makeTorus(float majorRadius, float minorRadius, int majorSegments = 48,
                   int minorSegments = 24);
// `count` camera-facing quads of half-size `particleSize`, centres drawn from a seeded
// Gaussian-like distribution inside a ball of `radius` (deterministic for a given seed).
MeshData makeParticleCloud(int count, float radius, float particleSize, std::uint32_t seed);

// One mesh of a loaded file with the material the file gave it (if any).
struct LoadedMesh {
    MeshData mesh;
    std::optional<Material> material; // filled from the file's material; empty if it has none
};

// The largest vertex coordinate a mesh file may hold. Shaders and the voxelizer square
// differences and lengths in float: (2e18)^2 x 3 stays below FLT_MAX = 3.4e38, while
// vertices near 3e38 made bounds, extents and squared lengths overflow to inf (a black
// frame, a crash in grid fitting).
constexpr float kMaxMeshCoordinate = 1e18f;

// Loads every mesh of a glTF 2.0 (.gltf/.glb), OBJ or PLY file through assimp, with node
// transforms baked into the vertices. Throws veil::Error naming the file on any failure
// (missing file, parse error, no triangles, a coordinate beyond kMaxMeshCoordinate).
std::vector<LoadedMesh> loadMeshFile(const std::filesystem::path& path);

} // namespace veil::scene
