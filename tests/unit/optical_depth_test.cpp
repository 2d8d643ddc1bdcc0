// The bare-.vdb density scale's statistic against chord lengths known in closed form.
#include "vdb/optical_depth.h"

#include <gtest/gtest.h>

#include <cmath>

namespace veil::vdb {
namespace {

// Density `rho` in the voxels whose centres lie within `radius` voxels of the origin.
openvdb::FloatGrid::Ptr ball(double radius, float rho, double voxelSize) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
    auto acc = grid->getAccessor();
    const int r = static_cast<int>(std::ceil(radius));
    for (int z = -r; z <= r; ++z)
        for (int y = -r; y <= r; ++y)
            for (int x = -r; x <= r; ++x)
                if (x * x + y * y + z * z <= radius * radius) acc.setValue({x, y, z}, rho);
    return grid;
}

TEST(OpticalDepth, CubeAlongAnAxisIsItsSideTimesDensity) {
    // Every line of sight along z through a cube of side L has optical depth rho L.
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
    grid->fill(openvdb::CoordBBox({0, 0, 0}, {15, 15, 15}), 2.0f, true);
    const OpticalDepthStats s = medianOpticalDepth(*grid, {0, 0, -1}, 32);
    EXPECT_EQ(s.rays, 32 * 32);
    EXPECT_NEAR(s.median, 2.0 * 1.6, 1e-3 * 3.2);
}

TEST(OpticalDepth, BallMedianChordIsSqrtTwoRadius) {
    // Parallel rays spread evenly over a ball's disc: the impact parameter b has density
    // proportional to b, so the median b is R / sqrt(2) and the median chord
    // 2 sqrt(R^2 - R^2 / 2) = sqrt(2) R, whatever the direction. The voxelized surface is
    // within half a voxel of R (here 1/40 of R) and the lattice of rays is finite: 3%.
    const double voxel = 0.05, radiusVoxels = 20.0;
    const auto grid = ball(radiusVoxels, 0.5f, voxel);
    const double radius = (radiusVoxels + 0.5) * voxel; // the cells' extent
    const OpticalDepthStats s = medianOpticalDepth(*grid, {-0.3, -0.35, -1.0}, 48);
    EXPECT_GT(s.raysWithDensity, 48 * 48 / 4);
    EXPECT_NEAR(s.median, 0.5 * std::sqrt(2.0) * radius, 0.03 * 0.5 * std::sqrt(2.0) * radius);
}

TEST(OpticalDepth, EmptyGridHasNoMedian) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    EXPECT_EQ(medianOpticalDepth(*grid, {0, 0, 1}).median, 0.0);
    grid->tree().setValue({1, 2, 3}, -4.0f); // negative density counts as none
    const OpticalDepthStats s = medianOpticalDepth(*grid, {0, 0, 1}, 4);
    EXPECT_EQ(s.raysWithDensity, 0);
    EXPECT_EQ(s.median, 0.0);
}

} // namespace
} // namespace veil::vdb
