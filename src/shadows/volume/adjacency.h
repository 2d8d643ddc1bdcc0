// Edge adjacency of a triangle mesh for silhouette extraction (the `volume` shadow technique):
// the GL_TRIANGLES_ADJACENCY index buffer (six indices per triangle: v0 a01 v1 a12 v2 a20,
// a_ij = the vertex opposite edge (i, j) in the neighbouring triangle) and whether the mesh is
// a closed, consistently wound 2-manifold (every edge shared by exactly two triangles that
// traverse it in opposite directions). Vertices are welded by position first (within 1e-6 of the
// mesh's extent), so meshes with split normals (flat-shaded boxes: 24 vertices) or float seams
// (the sphere's and torus' phi = 2 pi column) are still closed.
//
// A mesh that is not a closed 2-manifold gets `closed` = false and a reason naming the first
// bad edge; the technique then extrudes every triangle on its own (the robust per-triangle
// fallback), which is exact for any triangle soup but costs three side quads per triangle.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace veil::shadows {

struct Adjacency {
    // 6 per triangle, indices into the mesh's vertices, welded: every position is always
    // named by the same index (the first vertex at it), so a triangle read as a neighbour
    // has the same vertex indices as the triangle itself.
    std::vector<std::uint32_t> indices;
    bool closed = false;
    std::string reason; // why the mesh is not closed (empty when closed)
    int boundaryEdges = 0, nonManifoldEdges = 0, degenerateTriangles = 0;
};

// Builds the adjacency of an indexed triangle list. Degenerate triangles (two equal welded
// vertices) are dropped from the closure test; the mesh stays closed if the rest is.
Adjacency buildAdjacency(const std::vector<glm::vec3>& positions,
                         const std::vector<std::uint32_t>& indices);

} // namespace veil::shadows
