// The scattered-light bake's local majorants (src/integrators/majorant_grid.h) against the grid
// they bound: on the Disney cloud (a real grid, placed by a rotation and a scale as a scene entry
// places it) no trilinear sample of the grid (OpenVDB's BoxSampler, the CPU's sampler; the GPU
// filters the same voxels) exceeds the majorant of the cell it falls in: samples near every
// leaf node's faces, where a neighbouring node's values reach in, and uniform ones over the
// whole box. With the footprint margin taken away (0 instead of 1 voxel) samples near the faces
// exceed their cells' majorants. Also: the majorants are local (well below the grid's largest
// value on average).
#include "grid/density_grid.h"
#include "integrators/majorant_grid.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <openvdb/tools/Count.h>
#include <openvdb/tools/Interpolation.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdio>
#include <random>

namespace veil::test {

namespace {

struct Placed {
    openvdb::FloatGrid::ConstPtr grid;
    glm::mat4 objectToWorld{1.0f};
    glm::dvec3 lo{1e300}, hi{-1e300};
};

Placed placedCloud(bool rotated) {
    Placed p;
    p.grid =
        volume::loadDensityGrid(dataDir() / "vdb-wdas-cloud/wdas_cloud_sixteenth.vdb", "density");
    p.objectToWorld = glm::scale(glm::mat4(1.0f), glm::vec3(0.01f));
    if (rotated) p.objectToWorld = glm::rotate(p.objectToWorld, 0.5f, glm::vec3(0.3f, 1.0f, 0.2f));
    const openvdb::CoordBBox b = p.grid->evalActiveVoxelBoundingBox();
    for (int c = 0; c < 8; ++c) {
        const openvdb::Vec3d i((c & 1) ? b.max().x() + 1 : b.min().x() - 1,
                               (c & 2) ? b.max().y() + 1 : b.min().y() - 1,
                               (c & 4) ? b.max().z() + 1 : b.min().z() - 1);
        const openvdb::Vec3d o = p.grid->transform().indexToWorld(i);
        const glm::dvec3 w(glm::dmat4(p.objectToWorld) * glm::dvec4(o.x(), o.y(), o.z(), 1.0));
        p.lo = glm::min(p.lo, w);
        p.hi = glm::max(p.hi, w);
    }
    return p;
}

// Samples of `sampled` (at index points of `grid`'s own index space mapped through
// sampled's transform) above the majorant of their cell: near every leaf of `grid` (within 2
// voxels of its box) and uniformly over the box.
struct Check {
    std::size_t samples = 0, above = 0;
    double worst = 0.0; // largest sample / majorant
};

Check check(const Placed& p, const openvdb::FloatGrid& sampled, const volume::MajorantGrid& m) {
    Check c;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto acc = sampled.getConstAccessor();
    const glm::dmat4 toWorld(p.objectToWorld);
    auto probe = [&](const openvdb::Vec3d& index) {
        const openvdb::Vec3d o = p.grid->transform().indexToWorld(index);
        const glm::dvec3 w(toWorld * glm::dvec4(o.x(), o.y(), o.z(), 1.0));
        if (glm::any(glm::lessThan(w, m.lo)) || glm::any(glm::greaterThan(w, m.hi))) return;
        const openvdb::Vec3d si = sampled.transform().worldToIndex(o);
        const double v = openvdb::tools::BoxSampler::sample(acc, si);
        const double bound = m.at(m.cellOf(w));
        ++c.samples;
        if (v > bound * (1.0 + 1e-6) + 1e-12) ++c.above;
        if (v > 0.0) c.worst = std::max(c.worst, v / std::max(bound, 1e-30));
    };
    for (auto leaf = p.grid->tree().cbeginLeaf(); leaf; ++leaf) {
        const openvdb::CoordBBox b = leaf->getNodeBoundingBox();
        for (int s = 0; s < 24; ++s) {
            // A point within 2 voxels of one of the six faces, outside or inside.
            openvdb::Vec3d q;
            for (int k = 0; k < 3; ++k)
                q[k] = b.min()[k] - 2.0 + u(rng) * (b.max()[k] - b.min()[k] + 4.0);
            const int axis = s % 3;
            q[axis] = (s / 3) % 2 ? b.max()[axis] + 2.0 * u(rng) - 1.0
                                  : b.min()[axis] - 2.0 * u(rng) + 1.0;
            probe(q);
        }
    }
    const openvdb::CoordBBox b = p.grid->evalActiveVoxelBoundingBox();
    for (int s = 0; s < 200000; ++s)
        probe(openvdb::Vec3d(b.min().x() + u(rng) * (b.max().x() - b.min().x()),
                             b.min().y() + u(rng) * (b.max().y() - b.min().y()),
                             b.min().z() + u(rng) * (b.max().z() - b.min().z())));
    return c;
}

// Cells of `voxels` voxels of the grid (world size: 0.01 x its voxel size).
volume::MajorantGrid majorants(const Placed& p, double margin, double voxels) {
    volume::MajorantGrid m;
    m.lo = p.lo;
    m.hi = p.hi;
    const double cell = voxels * 0.01 * p.grid->voxelSize().x();
    m.dims = glm::clamp(glm::ivec3(glm::ceil((p.hi - p.lo) / cell)), glm::ivec3(1),
                        glm::ivec3(volume::kMajorantMaxCells));
    m.values = volume::gridMajorants(*p.grid, p.objectToWorld, p.lo, p.hi, m.dims, margin);
    for (float& v : m.values)
        v = std::max(v, 0.0f);
    return m;
}

} // namespace

TEST(MajorantGridTest, BoundsEveryTrilinearSampleOfARealGrid) {
    // Rotated, cells of one leaf node (8 voxels) as the bake makes them.
    const Placed p = placedCloud(true);
    const volume::MajorantGrid m = majorants(p, volume::coarseningMargin(0), 8.0);
    const Check c = check(p, *p.grid, m);
    std::printf("majorant grid %dx%dx%d: %zu samples, %zu above their cell's majorant, largest "
                "sample / majorant %.4f\n",
                m.dims.x, m.dims.y, m.dims.z, c.samples, c.above, c.worst);
    EXPECT_GT(c.samples, 200000u);
    EXPECT_EQ(c.above, 0u);
    EXPECT_GT(c.worst, 0.9); // tight somewhere: the cells holding the largest values

    // Local: the mean over the cells is far below the one majorant of all space.
    const float largest = openvdb::tools::minMax(p.grid->tree()).max();
    double sum = 0.0;
    for (float v : m.values)
        sum += v;
    std::printf("mean cell majorant / largest value %.3f\n", sum / m.values.size() / largest);
    EXPECT_LT(sum / m.values.size(), 0.5 * largest);

    // Axis-aligned with cells of one voxel: bounded with the margin; without it a neighbouring
    // leaf's values reach past the majorants.
    const Placed a = placedCloud(false);
    const Check fine = check(a, *a.grid, majorants(a, volume::coarseningMargin(0), 1.0));
    const Check bare = check(a, *a.grid, majorants(a, 0.0, 1.0));
    std::printf("cells of 1 voxel: %zu of %zu samples above; margin 0: %zu of %zu above\n",
                fine.above, fine.samples, bare.above, bare.samples);
    EXPECT_EQ(fine.above, 0u);
    EXPECT_GT(bare.above, 0u);
}

} // namespace veil::test
