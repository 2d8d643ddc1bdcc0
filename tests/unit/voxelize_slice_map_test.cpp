// Slice-map format and the CPU reference voxelizer, without GL: bit queries against brute
// force, coordinate round trips for ortho, perspective and local grids, the exact
// triangle/box test on hand-made cases and solid volumes against analytic ones.
#include "scene/mesh.h"
#include "voxelize/cpu_voxelizer.h"
#include "voxelize/slice_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace veil::voxelize {
namespace {

TEST(VoxelizeSliceMapTest, BitQueriesMatchBruteForce) {
    SliceMap m = makeOrthoGrid({0, 0, 0}, {1, 1, 1}, 3, 2, 100);
    std::mt19937 rng(7);
    for (int i = 0; i < 150; ++i)
        m.set(rng() % 3, rng() % 2, rng() % 100);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) {
            int first = -1, last = -1;
            for (int s = 0; s < 100; ++s)
                if (m.get(x, y, s)) {
                    if (first < 0) first = s;
                    last = s;
                }
            EXPECT_EQ(m.firstOccupied(x, y), first);
            EXPECT_EQ(m.lastOccupied(x, y), last);
            for (int s0 = 0; s0 < 100; s0 += 7)
                for (int s1 = s0; s1 < 100; s1 += 11) {
                    int n = 0;
                    for (int s = s0; s <= s1; ++s)
                        n += m.get(x, y, s);
                    EXPECT_EQ(m.countOccupied(x, y, s0, s1), n) << s0 << ".." << s1;
                }
            EXPECT_NEAR(m.thickness(x, y), m.countOccupied(x, y, 0, 99) * 0.01, 1e-12);
        }
}

TEST(VoxelizeSliceMapTest, OrthoAndPerspectiveRoundTrip) {
    SliceMap o = makeOrthoGrid({-1, -2, -3}, {1, 2, 3}, 8, 16, 40);
    SliceMap p = makePerspectiveGrid({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 40.0, 2.0, 20.0, 16, 12, 64);
    for (SliceMap* m : {&o, &p})
        for (int s = 0; s < m->slices; s += 5) {
            const glm::dvec3 c = m->cellCenter(3, 5, s);
            int x, y, k;
            ASSERT_TRUE(m->locate(c, x, y, k));
            EXPECT_EQ(glm::ivec3(x, y, k), glm::ivec3(3, 5, s));
        }
    // Ortho cell (x, y, s) is the box lo + [x, y, s] * voxel: voxel = (0.25, 0.25, 0.15).
    EXPECT_NEAR(glm::length(o.cellCenter(1, 2, 3) - glm::dvec3(-0.625, -1.375, -2.475)), 0.0,
                1e-12);
    // Perspective slices are equal steps of eye depth: centre of slice s at 2 + (s+.5)*18/64.
    const glm::dvec3 c = p.cellCenter(8, 6, 10); // a column next to the axis
    EXPECT_NEAR(10.0 - c.z, 2.0 + 10.5 * 18.0 / 64.0, 1e-9);
}

TEST(VoxelizeSliceMapTest, LocalSlicingSubdividesTheColumnRange) {
    SliceMap m = makeOrthoGrid({0, 0, 0}, {1, 1, 10}, 2, 1, 32);
    m.nearDepth = {0.5f, 0.1f};
    m.farDepth = {0.6f, 0.9f};
    int x, y, s;
    ASSERT_TRUE(m.locate({0.25, 0.5, 5.52}, x, y, s)); // t = 0.552 in [0.5, 0.6]
    EXPECT_EQ(s, 16);
    EXPECT_FALSE(m.locate({0.25, 0.5, 7.0}, x, y, s)); // beyond the column's far
    m.set(0, 0, 16);
    EXPECT_TRUE(m.occupied({0.25, 0.5, 5.52}));
    EXPECT_NEAR(m.thickness(0, 0), 1.0 / 32.0, 1e-6); // (0.6 - 0.5) * 10 / 32
}

TEST(VoxelizeCpuTest, TriangleBoxOverlapCases) {
    const glm::dvec3 c(0.0), h(0.5);
    // Through the box, touching a face, just missing a face, missing past a corner (only
    // the edge-cross axes separate: the triangle's AABB overlaps the box).
    EXPECT_TRUE(triangleBoxOverlap(c, h, {-2, -2, 0}, {2, -2, 0}, {0, 2, 0}));
    EXPECT_TRUE(triangleBoxOverlap(c, h, {0.5, -1, -1}, {0.5, 1, -1}, {0.5, 0, 1}));
    EXPECT_FALSE(triangleBoxOverlap(c, h, {0.5001, -1, -1}, {0.5001, 1, -1}, {0.5001, 0, 1}));
    EXPECT_FALSE(triangleBoxOverlap(c, h, {1.2, 0.0, 0}, {0.0, 1.2, 0}, {1.2, 1.2, 0}));
    EXPECT_TRUE(triangleBoxOverlap(c, h, {0.9, 0.0, 0}, {0.0, 0.9, 0}, {1.2, 1.2, 0}));
    // Random triangles against a dense point-sampling of the triangle: sampled points
    // inside the box prove overlap, so the test must say yes.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int i = 0; i < 300; ++i) {
        const glm::dvec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)),
            d(u(rng), u(rng), u(rng));
        bool sampled = false;
        for (int k = 0; k <= 40 && !sampled; ++k)
            for (int l = 0; k + l <= 40 && !sampled; ++l) {
                const glm::dvec3 p = a + (b - a) * (k / 40.0) + (d - a) * (l / 40.0);
                sampled = glm::all(glm::lessThanEqual(glm::abs(p), h));
            }
        if (sampled) {
            EXPECT_TRUE(triangleBoxOverlap(c, h, a, b, d)) << i;
        }
    }
}

TEST(VoxelizeCpuTest, SolidVolumesMatchAnalytic) {
    const double r = 1.0;
    const Triangles sphere = fromMesh(scene::makeSphere(float(r), 96, 48));
    SliceMap g = makeOrthoGrid({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 64, 64, 64);
    voxelizeSolidCpu(sphere, g);
    const double cell = std::pow(2.4 / 64.0, 3);
    // Tessellated sphere volume is slightly below 4/3 pi r^3; 2% covers both.
    EXPECT_NEAR(g.countSet() * cell, 4.0 / 3.0 * M_PI, 0.02 * 4.0 / 3.0 * M_PI);
    const Triangles box = fromMesh(scene::makeBox({1.0f, 0.5f, 0.75f}));
    voxelizeSolidCpu(box, g);
    EXPECT_NEAR(g.countSet() * cell, 0.375, 0.375 * 0.06);
    // The surface shell of a sphere holds the surface: area / voxel area within a factor.
    voxelizeSurfaceCpu(sphere, g);
    const double shell = g.countSet() * std::pow(2.4 / 64.0, 2);
    EXPECT_GT(shell, 4.0 * M_PI * 1.0);
    EXPECT_LT(shell, 4.0 * M_PI * 3.0);
}

} // namespace
} // namespace veil::voxelize
