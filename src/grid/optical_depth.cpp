#include "grid/optical_depth.h"

#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace veil::vdb {

OpticalDepthStats medianOpticalDepth(const openvdb::FloatGrid& grid, openvdb::Vec3d direction,
                                     int raysPerSide) {
    OpticalDepthStats out;
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty() || direction.length() <= 0.0 || raysPerSide < 1) return out;
    direction.normalize();
    // Index space: the sampler reads index coordinates; the box covers whole cells.
    const openvdb::math::Transform& xf = grid.transform();
    const openvdb::Vec3d lo = box.min().asVec3d() - 0.5, hi = box.max().asVec3d() + 0.5;
    // World corners of the box, their projection onto a basis (u, v) normal to the direction.
    openvdb::Vec3d u =
        std::abs(direction.x()) < 0.9 ? openvdb::Vec3d(1, 0, 0) : openvdb::Vec3d(0, 1, 0);
    u = (u - direction * u.dot(direction)).unit();
    const openvdb::Vec3d v = direction.cross(u);
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300, t0 = 1e300, t1 = -1e300;
    for (int c = 0; c < 8; ++c) {
        const openvdb::Vec3d p = xf.indexToWorld(openvdb::Vec3d(
            c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z()));
        u0 = std::min(u0, p.dot(u)), u1 = std::max(u1, p.dot(u));
        v0 = std::min(v0, p.dot(v)), v1 = std::max(v1, p.dot(v));
        t0 = std::min(t0, p.dot(direction)), t1 = std::max(t1, p.dot(direction));
    }
    const double voxel = std::min({xf.voxelSize().x(), xf.voxelSize().y(), xf.voxelSize().z()});
    // Trilinear interpolation reaches a voxel beyond the cells: integrate that too, so a line
    // through a uniform block sums the voxel values times their length exactly.
    const double reach = std::max({xf.voxelSize().x(), xf.voxelSize().y(), xf.voxelSize().z()});
    t0 -= reach, t1 += reach;
    const double span = t1 - t0;
    const int steps = static_cast<int>(std::clamp(std::ceil(span / (0.5 * voxel)), 1.0, 1024.0));
    const double dt = span / steps;
    // The sampler keeps a pointer to the accessor: it must outlive the sampler (a temporary
    // here was destroyed at the end of the statement; UBSan's vptr check found it).
    const openvdb::FloatGrid::ConstAccessor accessor = grid.getConstAccessor();
    openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler>
        sampler(accessor, xf);
    std::vector<double> depths;
    for (int j = 0; j < raysPerSide; ++j) {
        for (int i = 0; i < raysPerSide; ++i) {
            const double a = u0 + (u1 - u0) * (i + 0.5) / raysPerSide;
            const double b = v0 + (v1 - v0) * (j + 0.5) / raysPerSide;
            const openvdb::Vec3d origin = u * a + v * b + direction * t0;
            double tau = 0.0;
            for (int s = 0; s < steps; ++s) {
                const openvdb::Vec3d w = origin + direction * ((s + 0.5) * dt);
                tau += std::max(0.0, double(sampler.wsSample(w)));
            }
            ++out.rays;
            if (tau > 0.0) depths.push_back(tau * dt);
        }
    }
    out.raysWithDensity = static_cast<int>(depths.size());
    if (depths.empty()) return out;
    const std::size_t mid = depths.size() / 2;
    std::nth_element(depths.begin(), depths.begin() + mid, depths.end());
    out.median = depths[mid];
    if (depths.size() % 2 == 0) {
        const double below = *std::max_element(depths.begin(), depths.begin() + mid);
        out.median = 0.5 * (out.median + below);
    }
    return out;
}

} // namespace veil::vdb
