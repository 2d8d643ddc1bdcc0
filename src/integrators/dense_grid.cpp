#include "integrators/dense_grid.h"

#include <openvdb/tools/Interpolation.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace veil::volume {

DenseGrid::DenseGrid(const openvdb::FloatGrid& grid, const glm::dmat4& worldToObject) {
    const openvdb::math::Transform& xf = grid.transform();
    openvdb::CoordBBox box, active;
    if (!xf.isLinear() || !grid.tree().evalLeafBoundingBox(box)) return;
    if (grid.tree().evalActiveVoxelBoundingBox(active)) box.expand(active);
    box.expand(1); // trilinear samples within one voxel of the nodes read their neighbours
    const openvdb::Coord dim = box.dim();
    const std::size_t n = std::size_t(dim.x()) * dim.y() * dim.z();
    if (n == 0 || n > kDenseGridMaxVoxels) return;
    // World -> index is affine for a linear transform: probed at the origin and the unit axes.
    auto toIndex = [&](const glm::dvec3& w) {
        const glm::dvec3 o = glm::dvec3(worldToObject * glm::dvec4(w, 1.0));
        const openvdb::Vec3d i = xf.worldToIndex(openvdb::Vec3d(o.x, o.y, o.z));
        return glm::dvec3(i.x(), i.y(), i.z());
    };
    const glm::dvec3 origin = toIndex(glm::dvec3(0.0));
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 e(0.0);
        e[a] = 1.0;
        worldToIndex_[a] = toIndex(e) - origin;
    }
    worldToIndex_[3] = origin;
    min_ = box.min();
    size_ = glm::ivec3(dim.x(), dim.y(), dim.z());
    values_.resize(n);
    tbb::parallel_for(0, size_.z, [&](int z) {
        openvdb::FloatGrid::ConstAccessor acc = grid.getConstAccessor();
        for (int y = 0; y < size_.y; ++y)
            for (int x = 0; x < size_.x; ++x)
                values_[(std::size_t(z) * size_.y + y) * size_.x + x] =
                    acc.getValue(min_.offsetBy(x, y, z));
    });
}

bool DenseGrid::maxOver(const glm::dvec3& lo, const glm::dvec3& hi, float& out) const {
    if (!valid()) return false;
    glm::dvec3 a(1e300), b(-1e300);
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 w((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        const glm::dvec3 i = worldToIndex_ * glm::dvec4(w, 1.0);
        a = glm::min(a, i);
        b = glm::max(b, i);
    }
    // A sample at index point x reads voxels floor(x) and floor(x) + 1 per axis; one more on
    // each side for the rounding of the transform.
    const glm::dvec3 origin(min_.x(), min_.y(), min_.z());
    const glm::dvec3 first = glm::floor(a) - 1.0 - origin, last = glm::floor(b) + 2.0 - origin;
    if (glm::any(glm::lessThan(first, glm::dvec3(0.0))) ||
        glm::any(glm::greaterThanEqual(last, glm::dvec3(size_))))
        return false;
    const glm::ivec3 f(first), l(last);
    float m = -1e30f;
    for (int z = f.z; z <= l.z; ++z)
        for (int y = f.y; y <= l.y; ++y) {
            const float* row = &values_[(std::size_t(z) * size_.y + y) * size_.x];
            for (int x = f.x; x <= l.x; ++x)
                m = std::max(m, row[x]);
        }
    out = m;
    return true;
}

double DenseGrid::sample(const glm::dvec3& p, openvdb::FloatGrid::ConstAccessor& accessor) const {
    const glm::dvec3 idx = worldToIndex_ * glm::dvec4(p, 1.0);
    const glm::dvec3 f = glm::floor(idx);
    const glm::ivec3 i = glm::ivec3(f) - glm::ivec3(min_.x(), min_.y(), min_.z());
    if (glm::any(glm::lessThan(i, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(i + 1, size_)))
        return openvdb::tools::BoxSampler::sample(accessor, openvdb::Vec3R(idx.x, idx.y, idx.z));
    const glm::dvec3 uvw = idx - f;
    const std::size_t sx = 1, sy = std::size_t(size_.x), sz = sy * std::size_t(size_.y);
    const float* v = &values_[std::size_t(i.z) * sz + std::size_t(i.y) * sy + std::size_t(i.x)];
    // BoxSampler::trilinearInterpolation: z, then y, then x, each step rounded to float.
    auto lerp = [](float a, float b, double w) { return float(a + float((b - a) * w)); };
    auto zy = [&](const float* c) {
        return lerp(lerp(c[0], c[sz], uvw.z), lerp(c[sy], c[sy + sz], uvw.z), uvw.y);
    };
    return lerp(zy(v), zy(v + sx), uvw.x);
}

} // namespace veil::volume
