#include "shadows/volume/adjacency.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace veil::shadows {

namespace {
struct CellKey {
    long long x, y, z;
    bool operator==(const CellKey&) const = default;
};
struct CellHash {
    std::size_t operator()(const CellKey& k) const {
        return std::size_t(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
    }
};
} // namespace

Adjacency buildAdjacency(const std::vector<glm::vec3>& positions,
                         const std::vector<std::uint32_t>& indices) {
    // Weld positions closer than 1e-6 of the mesh's extent (procedural seams: the sphere's
    // phi = 2 pi column is not bit-equal to phi = 0 in float): each vertex takes the first
    // vertex within tolerance, searched in the 27 neighbouring cells of a grid of that size.
    glm::vec3 lo(0.0f), hi(0.0f);
    if (!positions.empty()) lo = hi = positions[0];
    for (const glm::vec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double tol = std::max(1e-6 * double(glm::length(hi - lo)), 1e-12);
    std::vector<std::uint32_t> weld(positions.size());
    std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> cells;
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3 p(positions[i]);
        const CellKey k{static_cast<long long>(std::floor(p.x / tol)),
                        static_cast<long long>(std::floor(p.y / tol)),
                        static_cast<long long>(std::floor(p.z / tol))};
        std::uint32_t found = std::uint32_t(i);
        for (int dz = -1; dz <= 1 && found == i; ++dz)
            for (int dy = -1; dy <= 1 && found == i; ++dy)
                for (int dx = -1; dx <= 1 && found == i; ++dx) {
                    const auto it = cells.find({k.x + dx, k.y + dy, k.z + dz});
                    if (it == cells.end()) continue;
                    for (std::uint32_t j : it->second)
                        if (glm::length(glm::dvec3(positions[j]) - p) <= tol) {
                            found = j;
                            break;
                        }
                }
        weld[i] = found;
        if (found == i) cells[k].push_back(found);
    }
    const std::size_t triangles = indices.size() / 3;
    // Directed edge (welded a -> welded b) -> the triangle's third vertex (original index),
    // with the number of triangles that use it.
    struct Use {
        std::uint32_t opposite;
        int count;
    };
    std::map<std::pair<std::uint32_t, std::uint32_t>, Use> edges;
    Adjacency adj;
    std::vector<bool> degenerate(triangles, false);
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t* v = &indices[3 * t];
        const std::uint32_t w[3] = {weld[v[0]], weld[v[1]], weld[v[2]]};
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) {
            degenerate[t] = true;
            ++adj.degenerateTriangles;
            continue;
        }
        for (int e = 0; e < 3; ++e) {
            auto [it, fresh] = edges.try_emplace({w[e], w[(e + 1) % 3]}, Use{w[(e + 2) % 3], 0});
            ++it->second.count;
        }
    }
    adj.indices.resize(6 * triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t* v = &indices[3 * t];
        const std::uint32_t w[3] = {weld[v[0]], weld[v[1]], weld[v[2]]};
        for (int e = 0; e < 3; ++e) {
            adj.indices[6 * t + 2 * e] = w[e];
            // No neighbour: the triangle's own opposite vertex (the shader never reads it for
            // a mesh that is not closed).
            adj.indices[6 * t + 2 * e + 1] = w[(e + 2) % 3];
        }
        if (degenerate[t]) continue;
        for (int e = 0; e < 3; ++e) {
            const auto a = w[e], b = w[(e + 1) % 3];
            const auto self = edges.find({a, b});
            const auto twin = edges.find({b, a});
            if (self->second.count > 1 || (twin != edges.end() && twin->second.count > 1)) {
                if (adj.nonManifoldEdges++ == 0)
                    adj.reason = fmt::format("edge ({}, {}) of triangle {} is shared by more than "
                                             "two triangles or wound the same way twice",
                                             v[e], v[(e + 1) % 3], t);
            } else if (twin == edges.end()) {
                if (adj.boundaryEdges++ == 0)
                    adj.reason = fmt::format("edge ({}, {}) of triangle {} is open (a boundary)",
                                             v[e], v[(e + 1) % 3], t);
            } else {
                adj.indices[6 * t + 2 * e + 1] = twin->second.opposite;
            }
        }
    }
    adj.closed = adj.boundaryEdges == 0 && adj.nonManifoldEdges == 0 &&
                 triangles > std::size_t(adj.degenerateTriangles);
    if (triangles == std::size_t(adj.degenerateTriangles)) adj.reason = "no triangle has area";
    return adj;
}

} // namespace veil::shadows
