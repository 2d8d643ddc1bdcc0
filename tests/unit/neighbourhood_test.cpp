// The neighbourhood mean of the depth-aware octaves (src/grid/neighbourhood.h) against
// means counted voxel by voxel through an accessor, and its interpolation against the
// trilinear formula at points of known weights.
#include "grid/neighbourhood.h"

#include <gtest/gtest.h>

#include <openvdb/openvdb.h>

namespace veil::test {

namespace {

// A 16^3 block of 1 at [0, 15]^3, one voxel of 2 at (20, 3, 3), a level-1 tile (one leaf's
// 8^3 voxels) of 0.5 at (-8, 0, 0), and an inactive voxel of 7 that must not count.
openvdb::FloatGrid::Ptr testGrid() {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.0f);
    auto acc = grid->getAccessor();
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                acc.setValue({x, y, z}, 1.0f);
    acc.setValue({20, 3, 3}, 2.0f);
    acc.setValueOff({21, 3, 3}, 7.0f);
    grid->tree().addTile(1, openvdb::Coord(-8, 0, 0), 0.5f, true);
    return grid;
}

// The mean over the 8^3 voxels of cell (cx, cy, cz), counted through an accessor: active
// voxels and tiles only.
double bruteMean(const openvdb::FloatGrid& grid, int cx, int cy, int cz) {
    auto acc = grid.getConstAccessor();
    double s = 0.0;
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const openvdb::Coord c(cx * 8 + x, cy * 8 + y, cz * 8 + z);
                if (acc.isValueOn(c)) s += acc.getValue(c);
            }
    return s / 512.0;
}

} // namespace

TEST(NeighbourhoodTest, CellMeansEqualVoxelByVoxelCounts) {
    const auto grid = testGrid();
    const volume::NeighbourhoodMean m = volume::neighbourhoodMean(*grid);
    EXPECT_EQ(m.origin, glm::ivec3(-1, 0, 0));
    EXPECT_EQ(m.size, glm::ivec3(4, 2, 2)); // cells -1 .. 2 in x, 0 .. 1 in y and z
    for (int z = -1; z <= 2; ++z)
        for (int y = -1; y <= 2; ++y)
            for (int x = -2; x <= 3; ++x)
                EXPECT_DOUBLE_EQ(m.at(x, y, z), bruteMean(*grid, x, y, z))
                    << "cell " << x << " " << y << " " << z;
    EXPECT_DOUBLE_EQ(m.at(2, 0, 0), 2.0 / 512.0);
    EXPECT_DOUBLE_EQ(m.at(-1, 0, 0), 0.5);
}

TEST(NeighbourhoodTest, SamplesAreTrilinearBetweenCellCentres) {
    const auto grid = testGrid();
    const volume::NeighbourhoodMean m = volume::neighbourhoodMean(*grid);
    // Cell centres: the cell's mean.
    EXPECT_DOUBLE_EQ(m.sample({3.5, 3.5, 3.5}), 1.0);
    EXPECT_DOUBLE_EQ(m.sample({-4.5, 3.5, 3.5}), 0.5);
    // Halfway between the centres of cells 1 and 2 in x (y, z at cell 0's centre).
    EXPECT_NEAR(m.sample({15.5, 3.5, 3.5}), 0.5 * (1.0 + 2.0 / 512.0), 1e-12);
    // A quarter of the way from cell -1's centre toward cell 0's in x, a quarter from cell 0
    // toward cell 1 in y: cells (-1,0) 0.5, (-1,1) 0, (0,0) 1, (0,1) 1.
    EXPECT_NEAR(m.sample({-2.5, 5.5, 3.5}), 0.75 * (0.75 * 0.5) + 0.25 * 1.0, 1e-12);
    // A quarter past the last row of cells in y toward the zero border.
    EXPECT_NEAR(m.sample({3.5, 13.5, 3.5}), 0.75, 1e-12);
    // Far outside: 0.
    EXPECT_EQ(m.sample({100.0, 3.5, 3.5}), 0.0);
    EXPECT_EQ(m.sample({3.5, -40.0, 3.5}), 0.0);
}

} // namespace veil::test
