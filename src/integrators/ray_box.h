// The parameter interval in which a ray o + t d crosses axis-aligned boxes, in double precision,
// and a grid's world box: the CPU references (cpu_reference.h, path_tracer.h) march or track
// only where a volume is.
#pragma once

#include <glm/glm.hpp>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>

namespace veil::volume {

// [a, b] of the ray inside the box [lo, hi] (slab method); false when it misses. A direction
// component of 0 keeps the whole line when the origin lies between that axis's planes.
inline bool rayBoxInterval(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo,
                           const glm::dvec3& hi, double& a, double& b) {
    a = -1e300;
    b = 1e300;
    for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < 1e-300) {
            if (o[k] < lo[k] || o[k] > hi[k]) return false;
            continue;
        }
        double ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
        if (ta > tb) std::swap(ta, tb);
        a = std::max(a, ta);
        b = std::min(b, tb);
    }
    return a < b;
}

// The union's hull of the intervals of several boxes (each with members lo and hi).
template <typename Boxes>
bool rayBoxesInterval(const glm::dvec3& o, const glm::dvec3& d, const Boxes& boxes, double& t0,
                      double& t1) {
    t0 = 1e300;
    t1 = -1e300;
    for (const auto& box : boxes) {
        double a, b;
        if (!rayBoxInterval(o, d, glm::dvec3(box.lo), glm::dvec3(box.hi), a, b)) continue;
        t0 = std::min(t0, a);
        t1 = std::max(t1, b);
    }
    return t0 < t1;
}

// The world-space box of the grid's active voxels, one voxel of margin on every side (the
// trilinear lookup reaches that far), through the grid's own transform and then `transform`
// (object to world).
inline void gridWorldBox(const openvdb::FloatGrid& grid, const glm::mat4& transform, glm::dvec3& lo,
                         glm::dvec3& hi) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    lo = glm::dvec3(1e300);
    hi = glm::dvec3(-1e300);
    for (int c = 0; c < 8; ++c) {
        const openvdb::Vec3d idx((c & 1) ? box.max().x() + 1 : box.min().x() - 1,
                                 (c & 2) ? box.max().y() + 1 : box.min().y() - 1,
                                 (c & 4) ? box.max().z() + 1 : box.min().z() - 1);
        const openvdb::Vec3d o = grid.indexToWorld(idx);
        const glm::dvec3 w =
            glm::dvec3(glm::dmat4(transform) * glm::dvec4(o.x(), o.y(), o.z(), 1.0));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
}

} // namespace veil::volume
