// A density grid's values copied into a dense array over its nodes' index box, for the path
// tracer's lookups (path_tracer.h): the trilinear sample at a world point is OpenVDB's
// BoxSampler's (the same eight voxels, the same interpolation order in the grid's float), read
// from the array instead of through the tree's accessor, whose walk and the two transforms
// before it were most of the CPU bake's time (profiled on the Disney cloud). Points whose
// eight voxels are not all in the array (beyond the nodes and their one voxel of margin) are
// sampled through an accessor as before. Only for linear grid transforms and boxes of at most
// kDenseGridMaxVoxels voxels; otherwise valid() is false and the caller samples the tree.
#pragma once

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace veil::volume {

inline constexpr std::size_t kDenseGridMaxVoxels = std::size_t(64) << 20; // 256 MiB of floats

class DenseGrid {
public:
    DenseGrid() = default;
    // `grid` placed in the world by `worldToObject` (world -> the grid's world space).
    DenseGrid(const openvdb::FloatGrid& grid, const glm::dmat4& worldToObject);

    bool valid() const { return !values_.empty(); }
    // The unscaled trilinear density at world point p (`accessor`: the grid's, for points
    // beyond the array).
    double sample(const glm::dvec3& p, openvdb::FloatGrid::ConstAccessor& accessor) const;

    // The largest value trilinear samples at world points in [lo, hi] can read (their eight
    // voxels'); false where some of those voxels lie beyond the array.
    bool maxOver(const glm::dvec3& lo, const glm::dvec3& hi, float& out) const;

private:
    glm::dmat4x3 worldToIndex_{1.0}; // affine
    openvdb::Coord min_{0};          // index of values_[0]
    glm::ivec3 size_{0};             // voxels per axis
    std::vector<float> values_;      // x fastest
};

} // namespace veil::volume
