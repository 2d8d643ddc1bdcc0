// The bare-.vdb density scale's statistic against chord lengths known in closed form.
#include "grid/optical_depth.h"

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

TEST(OpticalDepth, BallMedianChordFollowsTheImpactParameterDistribution) {
    // Parallel rays spread evenly over a disc of radius Rh meet density; the impact parameter
    // b has density proportional to b, so the median b is Rh / sqrt(2) and the median chord
    // through a ball of radius R is 2 sqrt(R^2 - Rh^2 / 2), whatever the direction. Here R is
    // the voxelized ball's volume-equivalent radius (voxel centres within R) and Rh = R + h:
    // trilinear interpolation reaches one voxel beyond the last one set, so rays through that
    // fringe meet (a little) density too. The lattice of 48^2 rays and the ragged surface
    // leave about 1%: 3%. (Rh = R would give sqrt(2) R, 9% higher: the fringe matters.)
    const double voxel = 0.05, radiusVoxels = 20.0;
    const auto grid = ball(radiusVoxels, 0.5f, voxel);
    const double r = radiusVoxels * voxel, rh = r + voxel;
    const double expected = 0.5 * 2.0 * std::sqrt(r * r - rh * rh / 2.0);
    const OpticalDepthStats s = medianOpticalDepth(*grid, {-0.3, -0.35, -1.0}, 48);
    EXPECT_GT(s.raysWithDensity, 48 * 48 / 4);
    EXPECT_NEAR(s.median, expected, 0.03 * expected);
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
