// Planning and converting a grid for the GPU on the CPU (grid_conversion.h).
#include "grid/grid_conversion.h"

#include "base/error.h"

#include <openvdb/tools/Interpolation.h>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <Imath/half.h>
#if defined(__x86_64__)
#include <cpuid.h>
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

namespace veil::volume {

namespace {

constexpr int kLeaf = 8;
constexpr int kBrick = kLeaf + 2; // one voxel of apron on each side

glm::mat4 affineIndexToWorld(const openvdb::FloatGrid& grid) {
    const openvdb::math::Transform& t = grid.transform();
    VEIL_CHECK(t.isLinear(),
               "grid '{}' has a non-linear (frustum) transform; only affine "
               "grid transforms are supported",
               grid.getName());
    const openvdb::Vec3d o = t.indexToWorld(openvdb::Vec3d(0, 0, 0));
    const openvdb::Vec3d x = t.indexToWorld(openvdb::Vec3d(1, 0, 0)) - o;
    const openvdb::Vec3d y = t.indexToWorld(openvdb::Vec3d(0, 1, 0)) - o;
    const openvdb::Vec3d z = t.indexToWorld(openvdb::Vec3d(0, 0, 1)) - o;
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(x.x(), x.y(), x.z(), 0.0f);
    m[1] = glm::vec4(y.x(), y.y(), y.z(), 0.0f);
    m[2] = glm::vec4(z.x(), z.y(), z.z(), 0.0f);
    m[3] = glm::vec4(o.x(), o.y(), o.z(), 1.0f);
    return m;
}

// Limits checked before anything is allocated. Index coordinates are handed to the shader as
// floats: beyond 2^24 neighbouring voxels have the same coordinate. The indirection table is
// dense over the leaves' bounding box: 2^25 entries (128 MiB) bound what sparse, far-apart
// data may cost in memory and upload time whatever the budget. Coarsening costs one pass over
// the leaves plus one fill per tile, so it is never the expensive part.
constexpr std::int64_t kMaxIndexCoord = std::int64_t(1) << 24;
constexpr double kMaxTableEntries = 33554432.0;
constexpr int kMaxCoarsening = 6;
constexpr double kBrickBytes = double(kBrick) * kBrick * kBrick * 2; // R16F

double product(const glm::dvec3& v) { return v.x * v.y * v.z; }

// Leaf-sized blocks holding active values: non-empty leaves and every 8^3 block of an active
// tile (a grid may be tiles only, and sdfToFogVolume fills a level set's interior with tiles;
// the accessor reads tile values like voxels). Dilated toward -x, -y, -z (see gpu_volume.h).
// Sorted (openvdb::Coord's order) and unique: the atlas order does not depend on threads.
std::vector<openvdb::Coord> brickOrigins(const openvdb::FloatGrid& grid) {
    std::vector<openvdb::Coord> origins;
    auto add = [&origins](const openvdb::Coord& o) {
        for (int c = 0; c < 8; ++c)
            origins.push_back(o - openvdb::Coord((c & 1) * kLeaf, ((c >> 1) & 1) * kLeaf,
                                                 ((c >> 2) & 1) * kLeaf));
    };
    origins.reserve(std::size_t(grid.tree().leafCount()) * 8);
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf)
        if (!leaf->isEmpty()) add(leaf->origin());
    auto tile = grid.tree().cbeginValueOn();
    tile.setMaxDepth(tile.getLeafDepth() - 1); // tiles only
    for (; tile; ++tile) {
        openvdb::CoordBBox b;
        tile.getBoundingBox(b);
        for (int z = b.min().z(); z <= b.max().z(); z += kLeaf)
            for (int y = b.min().y(); y <= b.max().y(); y += kLeaf)
                for (int x = b.min().x(); x <= b.max().x(); x += kLeaf)
                    add(openvdb::Coord(x, y, z));
    }
    tbb::parallel_sort(origins.begin(), origins.end());
    origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
    return origins;
}

// Leaf-sized blocks before dilation, counted without enumerating tiles.
double activeBlocks(const openvdb::FloatGrid& grid) {
    double blocks = double(grid.tree().leafCount());
    auto tile = grid.tree().cbeginValueOn();
    tile.setMaxDepth(tile.getLeafDepth() - 1);
    for (; tile; ++tile)
        blocks += double(tile.getVoxelCount()) / double(kLeaf * kLeaf * kLeaf);
    return blocks;
}

glm::ivec3 atlasLayout(std::size_t bricks) {
    const int side = std::max(1, static_cast<int>(std::ceil(std::cbrt(double(bricks)))));
    const int bx = side, by = side;
    const int bz = static_cast<int>((bricks + std::size_t(bx * by) - 1) / std::size_t(bx * by));
    return {bx, by, std::max(bz, 1)};
}

// What uploading `grid` takes, in 64-bit/double arithmetic (coordinates near the int32 limits
// overflow int spans). `whyNot` is empty when it fits the budget and the texture size limit.
struct Plan {
    bool dense = false;
    double bytes = 0.0; // a lower bound when the grid was found too large before enumeration
    std::vector<openvdb::Coord> origins;
    std::string whyNot;
};

Plan planUpload(const openvdb::FloatGrid& grid, const GpuVolumeOptions& options, int max3D) {
    Plan plan;
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty()) return plan;
    const glm::dvec3 lo(box.min().x(), box.min().y(), box.min().z());
    const glm::dvec3 hi(box.max().x(), box.max().y(), box.max().z());
    const glm::dvec3 dense = hi - lo + 3.0; // one voxel of apron on each side
    const double budget = double(options.budgetBytes);
    const double limit = double(max3D);
    auto tooWide = [&](const glm::dvec3& d, const char* what) {
        return fmt::format("its {} would be {}x{}x{} texels, over GL_MAX_3D_TEXTURE_SIZE {}", what,
                           d.x, d.y, d.z, max3D);
    };
    auto overBudget = [&](double bytes, bool lowerBound) {
        return fmt::format("needs {}{:.1f} MiB of GPU memory, over the budget of {:.1f} MiB",
                           lowerBound ? "at least " : "", bytes / 1048576.0, budget / 1048576.0);
    };
    if (product(dense) <= double(options.denseVoxelLimit) &&
        std::max({dense.x, dense.y, dense.z}) <= limit) {
        plan.dense = true;
        plan.bytes = product(dense) * 2.0;
        if (plan.bytes > budget) plan.whyNot = overBudget(plan.bytes, false);
        return plan;
    }
    // Bricks. First bounds that need no enumeration: tiles may stand for billions of blocks.
    const glm::dvec3 table = glm::floor((hi - lo) / double(kLeaf)) + 3.0;
    const double blocks = activeBlocks(grid);
    plan.bytes = blocks * kBrickBytes + product(table) * 4.0;
    if (product(table) > kMaxTableEntries) {
        plan.whyNot = fmt::format("its indirection table over {}x{}x{} leaves would have {:.3g} "
                                  "entries, over the limit of {:.3g} (active voxels far apart)",
                                  table.x, table.y, table.z, product(table), kMaxTableEntries);
        return plan;
    }
    if (std::max({table.x, table.y, table.z}) > limit) {
        plan.whyNot = tooWide(table, "indirection table");
        return plan;
    }
    if (plan.bytes > budget) {
        plan.whyNot = overBudget(plan.bytes, true);
        return plan;
    }
    plan.origins = brickOrigins(grid);
    const glm::ivec3 l = atlasLayout(plan.origins.size());
    const glm::dvec3 atlas = glm::dvec3(l) * double(kBrick);
    plan.bytes = product(glm::dvec3(l)) * kBrickBytes + product(table) * 4.0;
    if (plan.bytes > budget)
        plan.whyNot = overBudget(plan.bytes, false);
    else if (std::max({atlas.x, atlas.y, atlas.z}) > limit)
        plan.whyNot = tooWide(atlas, "brick atlas");
    return plan;
}

// Coordinates first: everything after works on spans that must fit.
void checkIndexRange(const openvdb::FloatGrid& grid) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    const std::int64_t m =
        std::max({std::abs(std::int64_t(box.min().x())), std::abs(std::int64_t(box.min().y())),
                  std::abs(std::int64_t(box.min().z())), std::abs(std::int64_t(box.max().x())),
                  std::abs(std::int64_t(box.max().y())), std::abs(std::int64_t(box.max().z()))});
    VEIL_CHECK(m < kMaxIndexCoord,
               "grid '{}' has active voxels at index coordinates [{} {} {}]..[{} {} {}], beyond "
               "+-2^24 where single-precision sampling cannot tell voxels apart (corrupt file?)",
               grid.getName(), box.min().x(), box.min().y(), box.min().z(), box.max().x(),
               box.max().y(), box.max().z());
}

// Voxel size x2 with a box filter: coarse voxel i covers fine voxels 2i and 2i + 1 on each axis
// (its centre at fine index 2i + 0.5) and takes their mean, so the optical depth is kept. Done
// here rather than with tools::resampleToMatch, which samples tiles voxel by voxel (15.7 s for a
// tile-only 1016^3 grid): a 2^3 group never straddles a tile, whose region is filled at once.
openvdb::FloatGrid::Ptr coarsen(const openvdb::FloatGrid& grid) {
    auto out = openvdb::FloatGrid::create(0.0f);
    openvdb::math::Transform::Ptr xf = grid.transform().copy();
    xf->preScale(2.0);
    xf->preTranslate(openvdb::Vec3d(0.25));
    out->setTransform(xf);
    out->setName(grid.getName());
    out->setGridClass(grid.getGridClass());
    auto half = [](const openvdb::Coord& c) {
        return openvdb::Coord(c.x() >> 1, c.y() >> 1, c.z() >> 1); // floor(c / 2)
    };
    auto tile = grid.tree().cbeginValueOn();
    tile.setMaxDepth(tile.getLeafDepth() - 1);
    for (; tile; ++tile) {
        openvdb::CoordBBox b;
        tile.getBoundingBox(b);
        out->tree().fill(openvdb::CoordBBox(half(b.min()), half(b.max())), *tile, true);
    }
    auto acc = out->getAccessor();
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        if (leaf->isEmpty()) continue;
        const openvdb::Coord o = leaf->origin();
        for (int z = 0; z < kLeaf; z += 2)
            for (int y = 0; y < kLeaf; y += 2)
                for (int x = 0; x < kLeaf; x += 2) {
                    float sum = 0.0f;
                    bool active = false;
                    for (int c = 0; c < 8; ++c) {
                        const openvdb::Coord v =
                            o + openvdb::Coord(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
                        sum += leaf->getValue(v);
                        active = active || leaf->isValueOn(v);
                    }
                    if (active) acc.setValue(half(o + openvdb::Coord(x, y, z)), sum * 0.125f);
                }
    }
    return out;
}

// Copies the values of `grid` over the index box [lo, lo + size) into `dst`, an array of
// `dims` texels (x fastest) of `stride` floats each, at texel (x, y, z) of the box:
// dst[((z * dims.y + y) * dims.x + x) * stride]. Leaf by leaf: a leaf's voxels from its
// buffer, a leaf-sized block without a leaf filled with its tile's (or the background) value,
// tiles being unions of such blocks. Every value equals accessor.getValue() of its voxel.
template <typename Accessor>
void copyBox(Accessor& acc, const openvdb::Coord& lo, const glm::ivec3& size, float* dst,
             const glm::ivec3& dims, std::size_t stride) {
    using Leaf = openvdb::FloatTree::LeafNodeType;
    const openvdb::Coord hi = lo + openvdb::Coord(size.x - 1, size.y - 1, size.z - 1);
    const int align = ~(kLeaf - 1); // floor to a multiple of 8, negative coordinates too
    for (int bz = lo.z() & align; bz <= hi.z(); bz += kLeaf)
        for (int by = lo.y() & align; by <= hi.y(); by += kLeaf)
            for (int bx = lo.x() & align; bx <= hi.x(); bx += kLeaf) {
                const openvdb::Coord block(bx, by, bz);
                const openvdb::Coord from = openvdb::Coord::maxComponent(block, lo);
                const openvdb::Coord to =
                    openvdb::Coord::minComponent(block + openvdb::Coord(kLeaf - 1), hi);
                const Leaf* leaf = acc.probeConstLeaf(block);
                const float tile = leaf ? 0.0f : acc.getValue(block);
                for (int z = from.z(); z <= to.z(); ++z)
                    for (int y = from.y(); y <= to.y(); ++y) {
                        float* row =
                            dst + ((std::size_t(z - lo.z()) * dims.y + (y - lo.y())) * dims.x +
                                   (from.x() - lo.x())) *
                                      stride;
                        if (!leaf) {
                            for (int x = from.x(); x <= to.x(); ++x, row += stride)
                                *row = tile;
                            continue;
                        }
                        const openvdb::Index at = Leaf::coordToOffset(openvdb::Coord(0, y, z));
                        for (int x = from.x(); x <= to.x(); ++x, row += stride)
                            *row = leaf->getValue(at + (openvdb::Index(x & (kLeaf - 1)) << 6));
                    }
            }
}

// copyBox() over a whole dense box, in parallel over slabs of leaf-aligned z.
void copyDense(const openvdb::FloatGrid& grid, const openvdb::Coord& lo, const glm::ivec3& size,
               float* dst, std::size_t stride) {
    const int first = lo.z() & ~(kLeaf - 1), last = lo.z() + size.z - 1;
    tbb::parallel_for(0, (last - first) / kLeaf + 1, [&](int slab) {
        auto acc = grid.getConstAccessor();
        const int z0 = std::max(lo.z(), first + slab * kLeaf);
        const int z1 = std::min(last, first + slab * kLeaf + kLeaf - 1);
        copyBox(acc, openvdb::Coord(lo.x(), lo.y(), z0), glm::ivec3(size.x, size.y, z1 - z0 + 1),
                dst + std::size_t(z0 - lo.z()) * size.y * size.x * stride, size, stride);
    });
}

void convertDense(const openvdb::FloatGrid& grid, GridConversion& out) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    out.stats.dense = true;
    const openvdb::Coord lo = box.min() - openvdb::Coord(1), hi = box.max() + openvdb::Coord(1);
    const openvdb::Coord d = hi - lo + openvdb::Coord(1);
    out.dataSize = glm::ivec3(d.x(), d.y(), d.z());
    out.values.assign(std::size_t(d.x()) * d.y() * d.z(), 0.0f);
    copyDense(grid, lo, out.dataSize, out.values.data(), 1);
    out.indexMin = glm::vec3(lo.x(), lo.y(), lo.z());
    out.indexMax = glm::vec3(hi.x(), hi.y(), hi.z());
    out.stats.gpuBytes = out.values.size() * 2;
}

void convertBricks(const openvdb::FloatGrid& grid, const std::vector<openvdb::Coord>& origins,
                   GridConversion& out) {
    VEIL_CHECK(!origins.empty(), "grid '{}' has no active leaves or tiles", grid.getName());
    out.stats.bricks = origins.size();
    openvdb::Coord lo = origins.front(), hi = origins.front();
    for (const auto& o : origins) {
        lo.minComponent(o);
        hi.maxComponent(o);
    }
    const openvdb::Coord span = hi - lo;
    const glm::ivec3 leaves(span.x() / kLeaf + 1, span.y() / kLeaf + 1, span.z() / kLeaf + 1);
    const glm::ivec3 per = atlasLayout(origins.size());
    const glm::ivec3 atlas = per * kBrick;
    out.bricksPerAxis = per;
    out.dataSize = atlas;
    out.tableSize = leaves;
    out.values.assign(std::size_t(atlas.x) * atlas.y * atlas.z, 0.0f);
    out.table.assign(std::size_t(leaves.x) * leaves.y * leaves.z, 0u);
    // Brick b fills its own 10^3 texels and its own table entry: no two tasks write one place.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, origins.size(), 64),
        [&](const tbb::blocked_range<std::size_t>& bricks) {
            auto acc = grid.getConstAccessor();
            for (std::size_t b = bricks.begin(); b != bricks.end(); ++b) {
                const openvdb::Coord& o = origins[b];
                const int bi = static_cast<int>(b);
                const glm::ivec3 slot(bi % per.x, (bi / per.x) % per.y, bi / (per.x * per.y));
                const glm::ivec3 base = slot * kBrick;
                copyBox(acc, o - openvdb::Coord(1), glm::ivec3(kBrick),
                        &out.values[(std::size_t(base.z) * atlas.y + base.y) * atlas.x + base.x],
                        atlas, 1);
                const openvdb::Coord d = o - lo;
                const glm::ivec3 l(d.x() / kLeaf, d.y() / kLeaf, d.z() / kLeaf);
                out.table[(std::size_t(l.z) * leaves.y + l.y) * leaves.x + l.x] =
                    static_cast<std::uint32_t>(b + 1);
            }
        });
    out.leafOrigin = glm::ivec3(lo.x(), lo.y(), lo.z()) / kLeaf;
    out.indexMin = glm::vec3(lo.x(), lo.y(), lo.z());
    // The apron holds voxel origin + 8, so samples up to (but excluding) the last leaf's end + 1
    // are filtered correctly.
    out.indexMax = glm::vec3(hi.x() + kLeaf, hi.y() + kLeaf, hi.z() + kLeaf);
    out.stats.gpuBytes = out.values.size() * 2 + out.table.size() * 4;
}

// The whole-voxel offset from the conversion's index space to `grid`'s when both grids have
// the same voxels (voxel size and axes equal, origins a whole number of voxels apart, to 1e-9
// of a voxel): the channel's value at a texel is then the value of one voxel of `grid`, copied
// (as exact as resampling at that voxel's centre, which through the conversion's float
// index-to-world matrix may land off it by rounding). nullopt otherwise (resampled).
std::optional<openvdb::Coord> voxelOffset(const GridConversion& c, const openvdb::FloatGrid& grid) {
    if (!c.transform || !c.transform->isLinear() || !grid.transform().isLinear())
        return std::nullopt;
    auto map = [&](double x, double y, double z) {
        return grid.worldToIndex(c.transform->indexToWorld(openvdb::Vec3d(x, y, z)));
    };
    const openvdb::Vec3d o = map(0, 0, 0);
    const openvdb::Vec3d whole(std::round(o.x()), std::round(o.y()), std::round(o.z()));
    auto near = [](const openvdb::Vec3d& a, const openvdb::Vec3d& b) {
        const openvdb::Vec3d d = a - b;
        return std::max({std::abs(d.x()), std::abs(d.y()), std::abs(d.z())}) <= 1e-9;
    };
    if (!near(o, whole) ||
        std::abs(whole.x()) + std::abs(whole.y()) + std::abs(whole.z()) > double(kMaxIndexCoord))
        return std::nullopt;
    for (int axis = 0; axis < 3; ++axis) {
        openvdb::Vec3d unit(0.0);
        unit[axis] = 1.0;
        if (!near(map(unit.x(), unit.y(), unit.z()) - o, unit)) return std::nullopt;
    }
    return openvdb::Coord(int(whole.x()), int(whole.y()), int(whole.z()));
}

GridConversion convert(const openvdb::FloatGrid& grid, const GpuVolumeOptions& options, int max3D) {
    VEIL_CHECK(grid.activeVoxelCount() > 0, "empty density grid");
    GridConversion out;
    out.name = grid.getName();
    out.stats.gridBytes = grid.memUsage();
    checkIndexRange(grid);
    max3D = max3D > 0 ? max3D : 256; // GL 4.5 guarantees at least 2048
    openvdb::FloatGrid::ConstPtr coarsened;
    const openvdb::FloatGrid* g = &grid;
    Plan plan = planUpload(*g, options, max3D);
    while (!plan.whyNot.empty()) {
        VEIL_CHECK(!options.refuseOverBudget,
                   "grid '{}': {} (raise render.volume_budget_mib or set volume_over_budget to "
                   "coarsen)",
                   grid.getName(), plan.whyNot);
        VEIL_CHECK(out.stats.coarsened < kMaxCoarsening,
                   "grid '{}' does not fit even coarsened {} "
                   "times: it {}",
                   grid.getName(), kMaxCoarsening, plan.whyNot);
        if (out.coarsenedBecause.empty()) out.coarsenedBecause = plan.whyNot;
        coarsened = coarsen(*g);
        g = coarsened.get();
        ++out.stats.coarsened;
        VEIL_CHECK(g->activeVoxelCount() > 0, "grid '{}' {}, and coarsened it is empty",
                   grid.getName(), out.coarsenedBecause);
        plan = planUpload(*g, options, max3D);
    }
    out.stats.activeVoxels = g->activeVoxelCount();
    out.indexToWorld = affineIndexToWorld(*g);
    out.transform = g->constTransformPtr();
    if (plan.dense)
        convertDense(*g, out);
    else
        convertBricks(*g, plan.origins, out);
    if (options.neighbourhood) {
        out.neighbourhood = neighbourhoodMean(*g);
        out.stats.gpuBytes += out.neighbourhood.mean.size() * 4;
    }
    return out;
}

#if defined(__x86_64__)
// F16C and AVX on this CPU, with the YMM state saved by the OS (XCR0 bits 1 and 2). By CPUID
// rather than __builtin_cpu_supports, which clang does not know "f16c" for.
bool hasF16c() {
    unsigned a = 0, b = 0, c = 0, d = 0;
    if (!__get_cpuid(1, &a, &b, &c, &d)) return false;
    if (!(c & bit_OSXSAVE) || !(c & bit_AVX) || !(c & bit_F16C)) return false;
    unsigned lo = 0, hi = 0;
    __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    return (lo & 6u) == 6u;
}

__attribute__((target("avx,f16c"))) void toHalfF16c(const float* in, std::uint16_t* out,
                                                    std::size_t n) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8)
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i),
                         _mm256_cvtps_ph(_mm256_loadu_ps(in + i), _MM_FROUND_TO_NEAREST_INT));
    for (; i < n; ++i)
        out[i] = _cvtss_sh(in[i], _MM_FROUND_TO_NEAREST_INT);
}
#endif

// `in` as half floats into `out`, in TBB tasks of 256 K texels.
void packHalfArray(const std::vector<float>& in, std::vector<std::uint16_t>& out) {
    out.resize(in.size());
    constexpr std::size_t kChunk = std::size_t(1) << 18;
    tbb::parallel_for(std::size_t(0), (in.size() + kChunk - 1) / kChunk, [&](std::size_t k) {
        const std::size_t first = k * kChunk, n = std::min(kChunk, in.size() - first);
        toHalf(in.data() + first, out.data() + first, n);
    });
}

} // namespace

void toHalf(const float* in, std::uint16_t* out, std::size_t n) {
#if defined(__x86_64__)
    static const bool f16c = hasF16c();
    if (f16c) return toHalfF16c(in, out, n);
#endif
    for (std::size_t i = 0; i < n; ++i)
        out[i] = imath_float_to_half(in[i]);
}

void packHalf(GridConversion& c) {
    packHalfArray(c.values, c.halfValues);
    packHalfArray(c.channel, c.halfChannel);
}

GridConversion convertGrid(const openvdb::FloatGrid& grid, const GpuVolumeOptions& options,
                           int max3D, int threads) {
    if (threads <= 0) return convert(grid, options, max3D);
    tbb::task_arena arena(threads);
    return arena.execute([&] { return convert(grid, options, max3D); });
}

void addChannel(GridConversion& c, const std::vector<openvdb::FloatGrid::Ptr>& grids) {
    VEIL_CHECK(grids.size() == 1 || grids.size() == 3, "addChannel: {} grids (1 or 3)",
               grids.size());
    const glm::ivec3 n = c.dataSize;
    const std::size_t components = grids.size() == 1 ? 1 : 4;
    c.channelComponents = int(components);
    c.channel.assign(c.values.size() * components, 0.0f);
    std::vector<std::optional<openvdb::Coord>> offsets;
    for (const auto& g : grids)
        offsets.push_back(voxelOffset(c, *g));
    // Index coordinate of the conversion -> world (the grid's own transform, before the scene
    // entry's) -> index coordinate of each grid: for the grids whose voxels are not the
    // conversion's.
    const glm::dmat4 toWorld(c.indexToWorld);
    using Accessors = std::vector<openvdb::FloatGrid::ConstAccessor>;
    auto accessors = [&grids] {
        Accessors a;
        for (const auto& g : grids)
            a.push_back(g->getConstAccessor());
        return a;
    };
    auto sample = [&](Accessors& acc, std::size_t k, const glm::ivec3& texel,
                      const glm::dvec3& index) {
        const glm::dvec3 w = glm::dvec3(toWorld * glm::dvec4(index, 1.0));
        c.channel[((std::size_t(texel.z) * n.y + texel.y) * n.x + texel.x) * components + k] =
            openvdb::tools::BoxSampler::sample(
                acc[k], grids[k]->worldToIndex(openvdb::Vec3d(w.x, w.y, w.z)));
    };
    if (c.stats.dense) {
        const openvdb::Coord lo(int(c.indexMin.x), int(c.indexMin.y), int(c.indexMin.z));
        for (std::size_t k = 0; k < grids.size(); ++k) {
            if (offsets[k]) {
                copyDense(*grids[k], lo + *offsets[k], n, c.channel.data() + k, components);
                continue;
            }
            tbb::parallel_for(0, n.z, [&](int z) {
                Accessors acc = accessors();
                for (int y = 0; y < n.y; ++y)
                    for (int x = 0; x < n.x; ++x)
                        sample(acc, k, {x, y, z}, glm::dvec3(c.indexMin) + glm::dvec3(x, y, z));
            });
        }
    } else {
        // The bricks the density conversion made (its indirection table), nothing else.
        const glm::ivec3 t = c.tableSize, per = c.bricksPerAxis;
        tbb::parallel_for(0, t.z, [&](int lz) {
            Accessors acc = accessors();
            for (int ly = 0; ly < t.y; ++ly)
                for (int lx = 0; lx < t.x; ++lx) {
                    const std::uint32_t b = c.table[(std::size_t(lz) * t.y + ly) * t.x + lx];
                    if (b == 0) continue;
                    const int bi = int(b - 1);
                    const glm::ivec3 base =
                        glm::ivec3(bi % per.x, (bi / per.x) % per.y, bi / (per.x * per.y)) * kBrick;
                    const glm::ivec3 origin = (c.leafOrigin + glm::ivec3(lx, ly, lz)) * kLeaf;
                    for (std::size_t k = 0; k < grids.size(); ++k) {
                        if (offsets[k]) {
                            const openvdb::Coord lo =
                                openvdb::Coord(origin.x - 1, origin.y - 1, origin.z - 1) +
                                *offsets[k];
                            copyBox(
                                acc[k], lo, glm::ivec3(kBrick),
                                &c.channel[((std::size_t(base.z) * n.y + base.y) * n.x + base.x) *
                                               components +
                                           k],
                                n, components);
                            continue;
                        }
                        for (int z = 0; z < kBrick; ++z)
                            for (int y = 0; y < kBrick; ++y)
                                for (int x = 0; x < kBrick; ++x)
                                    sample(acc, k, base + glm::ivec3(x, y, z),
                                           glm::dvec3(origin + glm::ivec3(x - 1, y - 1, z - 1)));
                    }
                }
        });
    }
    c.stats.gpuBytes += c.channel.size() * 2;
}

std::size_t estimateGpuBytes(const openvdb::FloatGrid& grid, const GpuVolumeOptions& options) {
    const Plan plan = planUpload(grid, options, std::numeric_limits<int>::max());
    return plan.bytes >= double(std::numeric_limits<std::size_t>::max())
               ? std::numeric_limits<std::size_t>::max()
               : static_cast<std::size_t>(plan.bytes);
}

} // namespace veil::volume
