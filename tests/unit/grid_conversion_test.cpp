// The CPU conversion of a grid for the GPU (grid/grid_conversion.h): multithreaded it equals
// the single-threaded conversion bit for bit, and every active voxel of the grid is found
// where the marcher looks for it (table -> brick -> texel, or the dense box), read straight
// from the grid with an accessor.
#include "grid/density_grid.h"
#include "grid/grid_conversion.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

namespace veil::test {

namespace {

void expectSame(const volume::GridConversion& a, const volume::GridConversion& b) {
    EXPECT_EQ(a.stats.dense, b.stats.dense);
    EXPECT_EQ(a.stats.bricks, b.stats.bricks);
    EXPECT_EQ(a.stats.gpuBytes, b.stats.gpuBytes);
    EXPECT_EQ(a.stats.coarsened, b.stats.coarsened);
    EXPECT_EQ(a.stats.activeVoxels, b.stats.activeVoxels);
    EXPECT_EQ(a.dataSize, b.dataSize);
    EXPECT_EQ(a.tableSize, b.tableSize);
    EXPECT_EQ(a.leafOrigin, b.leafOrigin);
    EXPECT_EQ(a.indexMin, b.indexMin);
    EXPECT_EQ(a.indexMax, b.indexMax);
    EXPECT_EQ(a.indexToWorld, b.indexToWorld);
    ASSERT_EQ(a.values.size(), b.values.size());
    EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)), 0);
    EXPECT_EQ(a.table, b.table);
}

// Every active voxel of `grid` read through the conversion's layout, as the shaders do.
void expectVoxelsFound(const openvdb::FloatGrid& grid, const volume::GridConversion& c) {
    std::size_t checked = 0, wrong = 0;
    for (auto v = grid.cbeginValueOn(); v; ++v) {
        if (!v.isVoxelValue()) continue;
        const openvdb::Coord p = v.getCoord();
        const glm::ivec3 q(p.x(), p.y(), p.z());
        float got = 0.0f;
        if (c.stats.dense) {
            const glm::ivec3 d = q - glm::ivec3(c.indexMin);
            got = c.values[(std::size_t(d.z) * c.dataSize.y + d.y) * c.dataSize.x + d.x];
        } else {
            const glm::ivec3 leaf = glm::ivec3(glm::floor(glm::vec3(q) / 8.0f));
            const glm::ivec3 l = leaf - c.leafOrigin;
            const std::uint32_t b =
                c.table[(std::size_t(l.z) * c.tableSize.y + l.y) * c.tableSize.x + l.x];
            ASSERT_GT(b, 0u) << "voxel in a leaf without a brick";
            const int bi = int(b - 1);
            const glm::ivec3 per = c.bricksPerAxis;
            const glm::ivec3 slot(bi % per.x, (bi / per.x) % per.y, bi / (per.x * per.y));
            const glm::ivec3 t = slot * 10 + (q - leaf * 8) + 1;
            got = c.values[(std::size_t(t.z) * c.dataSize.y + t.y) * c.dataSize.x + t.x];
        }
        ++checked;
        wrong += got != *v;
    }
    EXPECT_GT(checked, 1000u);
    EXPECT_EQ(wrong, 0u);
}

} // namespace

TEST(GridConversionTest, MultithreadedEqualsSingleThreadedBitForBit) {
    // Four threads even on a two-core machine, so that tasks really interleave.
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 4);
    const auto grid = volume::makeProceduralGrid("smoke-ball", glm::vec3(1.0f), 1.0f / 80.0f, 3);
    ASSERT_GT(grid->activeVoxelCount(), 100000u); // about 1500 bricks: many TBB tasks
    volume::GpuVolumeOptions bricks;
    bricks.denseVoxelLimit = 0; // force the atlas on a small grid
    volume::GpuVolumeOptions dense;
    volume::GpuVolumeOptions coarse = bricks;
    coarse.budgetBytes = volume::estimateGpuBytes(*grid, bricks) / 3;
    for (const auto& [name, options] :
         {std::pair{"bricks", bricks}, std::pair{"dense", dense}, std::pair{"coarse", coarse}}) {
        SCOPED_TRACE(name);
        const volume::GridConversion one = volume::convertGrid(*grid, options, 2048, 1);
        const volume::GridConversion many = volume::convertGrid(*grid, options, 2048, 4);
        expectSame(one, many);
        EXPECT_EQ(one.stats.dense, std::string(name) == "dense");
        EXPECT_EQ(one.stats.coarsened > 0, std::string(name) == "coarse");
        if (one.stats.coarsened == 0) expectVoxelsFound(*grid, many);
    }
}

} // namespace veil::test
