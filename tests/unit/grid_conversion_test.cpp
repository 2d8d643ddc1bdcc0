// The CPU conversion of a grid for the GPU (grid/grid_conversion.h): multithreaded it equals
// the single-threaded conversion bit for bit, and every active voxel of the grid is found
// where the marcher looks for it (table -> brick -> texel, or the dense box), read straight
// from the grid with an accessor. The emission channel (addChannel(), copied leaf by leaf when
// the channel grid has the density's voxels) equals resampling the channel grid at every texel
// as the conversion did before it copied. The half floats made for the upload (packHalf())
// are Imath's conversion of every texel.
#include "grid/density_grid.h"
#include "grid/grid_conversion.h"

#include <Imath/half.h>
#include <gtest/gtest.h>
#include <openvdb/tools/Interpolation.h>
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

// The channel as addChannel() made it before it copied: one grid trilinearly sampled at every
// texel of the layout (index -> the conversion's float indexToWorld -> the grid's index).
std::vector<float> resampledChannel(const volume::GridConversion& c,
                                    const openvdb::FloatGrid& grid) {
    const glm::ivec3 n = c.dataSize;
    std::vector<float> out(c.values.size(), 0.0f);
    auto acc = grid.getConstAccessor();
    auto sample = [&](const glm::ivec3& texel, const glm::dvec3& index) {
        const glm::dvec3 w = glm::dvec3(glm::dmat4(c.indexToWorld) * glm::dvec4(index, 1.0));
        out[(std::size_t(texel.z) * n.y + texel.y) * n.x + texel.x] =
            openvdb::tools::BoxSampler::sample(acc,
                                               grid.worldToIndex(openvdb::Vec3d(w.x, w.y, w.z)));
    };
    if (c.stats.dense) {
        for (int z = 0; z < n.z; ++z)
            for (int y = 0; y < n.y; ++y)
                for (int x = 0; x < n.x; ++x)
                    sample({x, y, z}, glm::dvec3(c.indexMin) + glm::dvec3(x, y, z));
        return out;
    }
    const glm::ivec3 t = c.tableSize, per = c.bricksPerAxis;
    for (int lz = 0; lz < t.z; ++lz)
        for (int ly = 0; ly < t.y; ++ly)
            for (int lx = 0; lx < t.x; ++lx) {
                const std::uint32_t b = c.table[(std::size_t(lz) * t.y + ly) * t.x + lx];
                if (b == 0) continue;
                const int bi = int(b - 1);
                const glm::ivec3 base =
                    glm::ivec3(bi % per.x, (bi / per.x) % per.y, bi / (per.x * per.y)) * 10;
                const glm::ivec3 origin = (c.leafOrigin + glm::ivec3(lx, ly, lz)) * 8;
                for (int z = 0; z < 10; ++z)
                    for (int y = 0; y < 10; ++y)
                        for (int x = 0; x < 10; ++x)
                            sample(base + glm::ivec3(x, y, z),
                                   glm::dvec3(origin + glm::ivec3(x - 1, y - 1, z - 1)));
            }
    return out;
}

// Texels whose values differ (-0 and +0 count as equal: the resampling adds a zero weight
// times a difference of neighbours to the voxel's value).
std::size_t differing(const std::vector<float>& a, const std::vector<float>& b) {
    EXPECT_EQ(a.size(), b.size());
    std::size_t d = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        d += a[i] != b[i];
    return d;
}

} // namespace

// The EmberGen frame's "temperature" grid has the "flames" grid's voxels (and a wider extent,
// with tiles): the copy equals the resampling at every texel, for the atlas, the dense box,
// the temperature shifted by whole voxels (an origin 3, -2, 5 voxels away) and, resampled
// since its voxels are not the channel's, a coarsened conversion.
TEST(GridConversionTest, ChannelCopyEqualsResamplingOnARealGrid) {
    const std::string file =
        std::string(VEIL_DATA_DIR) + "/vdb-embergen-fire-burn/embergen_fire_a_50.vdb";
    const auto flames = volume::loadDensityGrid(file, "flames");
    const auto temperature = volume::loadDensityGrid(file, "temperature");
    auto shifted = temperature->deepCopy();
    shifted->transform().preTranslate(openvdb::Vec3d(-3, 2, -5)); // index i -> world of i - d
    volume::GpuVolumeOptions bricks, dense;
    bricks.denseVoxelLimit = 0; // coarsened too: an atlas, not a dense box
    dense.denseVoxelLimit = std::size_t(1) << 24;
    volume::GpuVolumeOptions coarse = bricks;
    coarse.budgetBytes = volume::estimateGpuBytes(*flames, bricks) / 3;
    for (const auto& [name, options] :
         {std::pair{"bricks", bricks}, std::pair{"dense", dense}, std::pair{"coarse", coarse}}) {
        SCOPED_TRACE(name);
        volume::GridConversion c = volume::convertGrid(*flames, options, 2048);
        ASSERT_EQ(c.stats.dense, std::string(name) == "dense");
        ASSERT_EQ(c.stats.coarsened > 0, std::string(name) == "coarse");
        for (const auto& grid : {temperature, shifted}) {
            volume::addChannel(c, {grid});
            ASSERT_EQ(c.channelComponents, 1);
            const std::vector<float> reference = resampledChannel(c, *grid);
            EXPECT_EQ(differing(c.channel, reference), 0u);
            std::size_t nonzero = 0;
            for (float v : reference)
                nonzero += v != 0.0f;
            EXPECT_GT(nonzero, 50000u); // the fire's temperature, not an empty channel
        }
        // Three grids (a colour emission): RGBA texels, each component its grid's.
        const std::vector<openvdb::FloatGrid::Ptr> rgb{shifted, flames, temperature};
        volume::addChannel(c, rgb);
        ASSERT_EQ(c.channelComponents, 4);
        for (std::size_t k = 0; k < 4; ++k) {
            std::vector<float> component(c.values.size());
            for (std::size_t i = 0; i < component.size(); ++i)
                component[i] = c.channel[i * 4 + k];
            EXPECT_EQ(differing(component, k < 3 ? resampledChannel(c, *rgb[k])
                                                 : std::vector<float>(c.values.size(), 0.0f)),
                      0u)
                << k;
        }
    }
}

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

// packHalf (on the prefetch workers) makes the texels the upload used to convert itself: each
// one Imath's IEEE half of the float, rounded to nearest even, across the TBB chunks (a
// conversion of more than one chunk, 256 K texels) and for the emission channel too.
TEST(GridConversionTest, PackHalfEqualsImathsConversionOfEveryTexel) {
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 4);
    const auto grid = volume::makeProceduralGrid("smoke-ball", glm::vec3(1.0f), 1.0f / 80.0f, 3);
    volume::GpuVolumeOptions bricks;
    bricks.denseVoxelLimit = 0;
    volume::GridConversion c = volume::convertGrid(*grid, bricks, 2048);
    volume::addChannel(c, {grid});
    // Values between halves' steps too, and a few beyond the half range.
    for (std::size_t i = 0; i < c.values.size(); i += 97)
        c.values[i] = float(i % 1000) * 1.0009765625e-3f + (i % 3 == 0 ? 70000.0f : 0.0f);
    ASSERT_GT(c.values.size(), std::size_t(3) << 18);
    volume::packHalf(c);
    ASSERT_EQ(c.halfValues.size(), c.values.size());
    ASSERT_EQ(c.halfChannel.size(), c.channel.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < c.values.size(); ++i)
        wrong += c.halfValues[i] != imath_float_to_half(c.values[i]);
    for (std::size_t i = 0; i < c.channel.size(); ++i)
        wrong += c.halfChannel[i] != imath_float_to_half(c.channel[i]);
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(c.bytes(), (c.values.size() + c.channel.size()) * 6 + c.table.size() * 4);
}

} // namespace veil::test
