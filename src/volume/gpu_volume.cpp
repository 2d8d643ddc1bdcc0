#include "volume/gpu_volume.h"

#include "base/error.h"
#include "base/log.h"

#include <openvdb/tools/GridTransformer.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <set>

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

// Leaf origins holding active voxels, dilated toward -x, -y, -z (see gpu_volume.h).
std::set<openvdb::Coord> brickOrigins(const openvdb::FloatGrid& grid) {
    std::set<openvdb::Coord> origins;
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        if (leaf->isEmpty()) continue;
        const openvdb::Coord o = leaf->origin();
        for (int c = 0; c < 8; ++c)
            origins.insert(o - openvdb::Coord((c & 1) * kLeaf, ((c >> 1) & 1) * kLeaf,
                                              ((c >> 2) & 1) * kLeaf));
    }
    return origins;
}

glm::ivec3 atlasLayout(std::size_t bricks) {
    const int side = std::max(1, static_cast<int>(std::ceil(std::cbrt(double(bricks)))));
    const int bx = side, by = side;
    const int bz = static_cast<int>((bricks + std::size_t(bx * by) - 1) / std::size_t(bx * by));
    return {bx, by, std::max(bz, 1)};
}

// R16F 3D texture with trilinear filtering and clamped edges, filled from `values`.
gpu::Texture makeDensityTexture(int x, int y, int z, const std::vector<float>& values) {
    gpu::Texture t(GL_TEXTURE_3D);
    t.storage3D(1, GL_R16F, x, y, z)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(t.id(), 0, 0, 0, 0, x, y, z, GL_RED, GL_FLOAT, values.data());
    return t;
}

bool useDense(const openvdb::CoordBBox& box, const GpuVolumeOptions& options) {
    const openvdb::Coord d = box.dim();
    return double(d.x() + 2) * (d.y() + 2) * (d.z() + 2) <= double(options.denseVoxelLimit);
}

openvdb::FloatGrid::Ptr coarsen(const openvdb::FloatGrid& grid) {
    auto out = openvdb::FloatGrid::create(0.0f);
    openvdb::math::Transform::Ptr xf = grid.transform().copy();
    xf->preScale(2.0);
    out->setTransform(xf);
    out->setName(grid.getName());
    out->setGridClass(grid.getGridClass());
    openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(grid, *out);
    return out;
}

} // namespace

std::size_t estimateGpuBytes(const openvdb::FloatGrid& grid, const GpuVolumeOptions& options) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty()) return 0;
    if (useDense(box, options)) {
        const openvdb::Coord d = box.dim();
        return std::size_t(d.x() + 2) * (d.y() + 2) * (d.z() + 2) * 2;
    }
    const std::size_t bricks = brickOrigins(grid).size();
    const glm::ivec3 l = atlasLayout(bricks);
    const openvdb::Coord d = box.dim();
    const std::size_t leaves =
        std::size_t(d.x() / kLeaf + 3) * (d.y() / kLeaf + 3) * (d.z() / kLeaf + 3);
    return std::size_t(l.x) * l.y * l.z * kBrick * kBrick * kBrick * 2 + leaves * 4;
}

GpuVolume::GpuVolume(openvdb::FloatGrid::ConstPtr grid, const glm::mat4& objectToWorld,
                     const GpuVolumeOptions& options) {
    VEIL_CHECK(grid && grid->activeVoxelCount() > 0, "empty density grid");
    stats_.gridBytes = grid->memUsage();
    openvdb::FloatGrid::ConstPtr g = grid;
    std::size_t bytes = estimateGpuBytes(*g, options);
    while (bytes > options.budgetBytes) {
        VEIL_CHECK(!options.refuseOverBudget,
                   "grid '{}' needs {:.1f} MiB of GPU memory, over the budget of {:.1f} MiB "
                   "(raise render.volume_budget_mib or set volume_over_budget to coarsen)",
                   grid->getName(), bytes / 1048576.0, options.budgetBytes / 1048576.0);
        VEIL_CHECK(stats_.coarsened < 6, "grid '{}' does not fit {:.1f} MiB even coarsened",
                   grid->getName(), options.budgetBytes / 1048576.0);
        g = coarsen(*g);
        ++stats_.coarsened;
        bytes = estimateGpuBytes(*g, options);
        log::warn("grid '{}' over the GPU budget: coarsened to voxel size x{} ({:.1f} MiB)",
                  grid->getName(), 1 << stats_.coarsened, bytes / 1048576.0);
    }
    stats_.activeVoxels = g->activeVoxelCount();
    indexToWorld_ = objectToWorld * affineIndexToWorld(*g);
    worldToIndex_ = glm::inverse(indexToWorld_);
    voxelSize_ = std::max({glm::length(glm::vec3(indexToWorld_[0])),
                           glm::length(glm::vec3(indexToWorld_[1])),
                           glm::length(glm::vec3(indexToWorld_[2]))});
    const openvdb::CoordBBox box = g->evalActiveVoxelBoundingBox();
    if (useDense(box, options))
        buildDense(*g, box);
    else
        buildBricks(*g);
}

void GpuVolume::buildDense(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box) {
    stats_.dense = true;
    const openvdb::Coord lo = box.min() - openvdb::Coord(1), hi = box.max() + openvdb::Coord(1);
    const openvdb::Coord d = hi - lo + openvdb::Coord(1);
    std::vector<float> values(std::size_t(d.x()) * d.y() * d.z());
    auto acc = grid.getConstAccessor();
    std::size_t i = 0;
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x)
                values[i++] = acc.getValue({x, y, z});
    data_ = makeDensityTexture(d.x(), d.y(), d.z(), values);
    indexMin_ = glm::vec3(lo.x(), lo.y(), lo.z());
    indexMax_ = glm::vec3(hi.x(), hi.y(), hi.z());
    stats_.gpuBytes = values.size() * 2;
}

void GpuVolume::buildBricks(const openvdb::FloatGrid& grid) {
    const std::set<openvdb::Coord> origins = brickOrigins(grid);
    stats_.bricks = origins.size();
    openvdb::Coord lo = *origins.begin(), hi = *origins.begin();
    for (const auto& o : origins) {
        lo.minComponent(o);
        hi.maxComponent(o);
    }
    const openvdb::Coord span = hi - lo;
    const openvdb::Coord leaves(span.x() / kLeaf + 1, span.y() / kLeaf + 1, span.z() / kLeaf + 1);
    bricksPerAxis_ = atlasLayout(origins.size());
    const glm::ivec3 atlas = bricksPerAxis_ * kBrick;
    VEIL_CHECK(atlas.x <= 2048 && atlas.y <= 2048 && atlas.z <= 2048,
               "grid '{}': {} bricks exceed a 2048^3 atlas", grid.getName(), origins.size());
    std::vector<float> values(std::size_t(atlas.x) * atlas.y * atlas.z, 0.0f);
    std::vector<std::uint32_t> table(std::size_t(leaves.x()) * leaves.y() * leaves.z(), 0u);
    auto acc = grid.getConstAccessor();
    std::uint32_t b = 0;
    for (const auto& o : origins) {
        const glm::ivec3 slot(b % bricksPerAxis_.x, (b / bricksPerAxis_.x) % bricksPerAxis_.y,
                              b / (bricksPerAxis_.x * bricksPerAxis_.y));
        const glm::ivec3 base = slot * kBrick;
        for (int z = 0; z < kBrick; ++z)
            for (int y = 0; y < kBrick; ++y)
                for (int x = 0; x < kBrick; ++x) {
                    const float v = acc.getValue(o + openvdb::Coord(x - 1, y - 1, z - 1));
                    values[(std::size_t(base.z + z) * atlas.y + base.y + y) * atlas.x + base.x +
                           x] = v;
                }
        const openvdb::Coord d = o - lo;
        const openvdb::Coord l(d.x() / kLeaf, d.y() / kLeaf, d.z() / kLeaf);
        table[(std::size_t(l.z()) * leaves.y() + l.y()) * leaves.x() + l.x()] = b + 1;
        ++b;
    }
    data_ = makeDensityTexture(atlas.x, atlas.y, atlas.z, values);
    indirection_ = gpu::Texture(GL_TEXTURE_3D);
    indirection_.storage3D(1, GL_R32UI, leaves.x(), leaves.y(), leaves.z())
        .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureSubImage3D(indirection_.id(), 0, 0, 0, 0, leaves.x(), leaves.y(), leaves.z(),
                        GL_RED_INTEGER, GL_UNSIGNED_INT, table.data());
    leafOrigin_ = glm::ivec3(lo.x(), lo.y(), lo.z()) / kLeaf;
    indexMin_ = glm::vec3(lo.x(), lo.y(), lo.z());
    // The apron holds voxel origin + 8, so samples up to (but excluding) the last leaf's end + 1
    // are filtered correctly.
    indexMax_ = glm::vec3(hi.x() + kLeaf, hi.y() + kLeaf, hi.z() + kLeaf);
    stats_.gpuBytes = values.size() * 2 + table.size() * 4;
}

void GpuVolume::worldBounds(glm::vec3& lo, glm::vec3& hi) const {
    lo = glm::vec3(1e30f);
    hi = glm::vec3(-1e30f);
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 p((c & 1) ? indexMax_.x : indexMin_.x, (c & 2) ? indexMax_.y : indexMin_.y,
                          (c & 4) ? indexMax_.z : indexMin_.z);
        const glm::vec3 w = glm::vec3(indexToWorld_ * glm::vec4(p, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
}

} // namespace veil::volume
