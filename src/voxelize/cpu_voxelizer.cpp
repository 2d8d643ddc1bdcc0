#include "voxelize/cpu_voxelizer.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>

namespace veil::voxelize {

namespace {

// Grid index space of an orthographic axis-aligned grid: p -> (p - lo) / voxel.
struct IndexSpace {
    glm::dvec3 lo, voxel;
    glm::ivec3 n;
    explicit IndexSpace(const SliceMap& g) {
        VEIL_CHECK(!g.perspective && !g.local(),
                   "the CPU reference voxelizer needs an orthographic grid with uniform slicing");
        glm::dvec3 hi;
        gridBounds(g, lo, hi);
        n = {g.width, g.height, g.slices};
        voxel = (hi - lo) / glm::dvec3(n);
    }
};

bool axisSeparates(const glm::dvec3& axis, const glm::dvec3& v0, const glm::dvec3& v1,
                   const glm::dvec3& v2, const glm::dvec3& h) {
    const double p0 = glm::dot(axis, v0), p1 = glm::dot(axis, v1), p2 = glm::dot(axis, v2);
    const double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
    // Closed boxes: touching (== r) is overlap.
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

} // namespace

bool triangleBoxOverlap(const glm::dvec3& c, const glm::dvec3& h, const glm::dvec3& a,
                        const glm::dvec3& b, const glm::dvec3& cc) {
    const glm::dvec3 v0 = a - c, v1 = b - c, v2 = cc - c;
    // Box face normals: the triangle's AABB against the box.
    for (int i = 0; i < 3; ++i) {
        if (std::min({v0[i], v1[i], v2[i]}) > h[i] || std::max({v0[i], v1[i], v2[i]}) < -h[i])
            return false;
    }
    const glm::dvec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
    // Triangle plane.
    const glm::dvec3 nrm = glm::cross(e[0], e[1]);
    if (axisSeparates(nrm, v0, v1, v2, h)) return false;
    // Edge x box axis cross products (a zero axis never separates).
    for (const glm::dvec3& ed : e) {
        for (int i = 0; i < 3; ++i) {
            glm::dvec3 u(0.0);
            u[i] = 1.0;
            if (axisSeparates(glm::cross(u, ed), v0, v1, v2, h)) return false;
        }
    }
    return true;
}

void voxelizeSurfaceCpu(const Triangles& tris, SliceMap& grid) {
    const IndexSpace is(grid);
    grid.allocate();
    const glm::dvec3 half = 0.5 * is.voxel;
    for (std::size_t t = 0; t < tris.count(); ++t) {
        const glm::dvec3 a = tris.vertices[3 * t], b = tris.vertices[3 * t + 1],
                         c = tris.vertices[3 * t + 2];
        const glm::dvec3 lo = (glm::min(a, glm::min(b, c)) - is.lo) / is.voxel;
        const glm::dvec3 hi = (glm::max(a, glm::max(b, c)) - is.lo) / is.voxel;
        glm::ivec3 i0, i1;
        for (int k = 0; k < 3; ++k) {
            // Closed cells: a vertex on a cell plane touches both neighbours.
            i0[k] = std::max(0, static_cast<int>(std::ceil(lo[k])) - 1);
            i1[k] = std::min(is.n[k] - 1, static_cast<int>(std::floor(hi[k])));
        }
        for (int z = i0.z; z <= i1.z; ++z)
            for (int y = i0.y; y <= i1.y; ++y)
                for (int x = i0.x; x <= i1.x; ++x) {
                    const glm::dvec3 centre = is.lo + (glm::dvec3(x, y, z) + 0.5) * is.voxel;
                    if (triangleBoxOverlap(centre, half, a, b, c)) grid.set(x, y, z);
                }
    }
}

void voxelizeSolidCpu(const Triangles& tris, SliceMap& grid) {
    const IndexSpace is(grid);
    grid.allocate();
    std::vector<std::vector<double>> crossings(static_cast<std::size_t>(is.n.x) * is.n.y);
    for (std::size_t t = 0; t < tris.count(); ++t) {
        // In index units, so column centres are at integer + 0.5.
        glm::dvec3 p[3];
        for (int k = 0; k < 3; ++k)
            p[k] = (glm::dvec3(tris.vertices[3 * t + k]) - is.lo) / is.voxel;
        double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
        if (area == 0.0) continue; // edge-on: no crossing
        if (area < 0.0) std::swap(p[1], p[2]), area = -area;
        const int x0 =
            std::max(0, static_cast<int>(std::floor(std::min({p[0].x, p[1].x, p[2].x}) - 0.5)));
        const int x1 =
            std::min(is.n.x - 1, static_cast<int>(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
        const int y0 =
            std::max(0, static_cast<int>(std::floor(std::min({p[0].y, p[1].y, p[2].y}) - 0.5)));
        const int y1 =
            std::min(is.n.y - 1, static_cast<int>(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double px = x + 0.5, py = y + 0.5;
                double w[3];
                bool inside = true;
                for (int k = 0; k < 3 && inside; ++k) {
                    const glm::dvec3 &a = p[(k + 1) % 3], &b = p[(k + 2) % 3];
                    w[k] = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
                    // Top-left rule (as GL rasterizers): a centre on an edge belongs to the
                    // triangle only for top or left edges, so shared edges count once.
                    const double dx = b.x - a.x, dy = b.y - a.y;
                    const bool topLeft = (dy == 0.0 && dx < 0.0) || dy < 0.0;
                    inside = w[k] > 0.0 || (w[k] == 0.0 && topLeft);
                }
                if (!inside) continue;
                const double z = (w[0] * p[0].z + w[1] * p[1].z + w[2] * p[2].z) / area;
                crossings[grid.columnIndex(x, y)].push_back(z);
            }
    }
    for (int y = 0; y < is.n.y; ++y)
        for (int x = 0; x < is.n.x; ++x) {
            std::vector<double>& zs = crossings[grid.columnIndex(x, y)];
            std::sort(zs.begin(), zs.end());
            std::size_t below = 0;
            for (int s = 0; s < is.n.z; ++s) {
                while (below < zs.size() && zs[below] < s + 0.5)
                    ++below;
                if (below % 2 == 1) grid.set(x, y, s);
            }
        }
}

} // namespace veil::voxelize
