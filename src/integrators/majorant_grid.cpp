#include "integrators/majorant_grid.h"

#include "integrators/path_tracer.h"

#include <algorithm>
#include <cmath>

namespace veil::volume {

glm::ivec3 MajorantGrid::cellOf(const glm::dvec3& p) const {
    const glm::dvec3 c = glm::floor((p - lo) / (hi - lo) * glm::dvec3(dims));
    return glm::clamp(glm::ivec3(c), glm::ivec3(0), dims - 1);
}

glm::ivec3 majorantDims(const scene::Scene& scene,
                        const std::vector<openvdb::FloatGrid::ConstPtr>& grids,
                        const glm::dvec3& lo, const glm::dvec3& hi, double voxelsPerCell) {
    const double cell = std::max(voxelsPerCell * finestVoxelSize(scene, grids), 1e-12);
    return glm::clamp(glm::ivec3(glm::ceil((hi - lo) / cell)), glm::ivec3(1),
                      glm::ivec3(kMajorantMaxCells));
}

double coarseningMargin(int levels) {
    // A coarse voxel's trilinear footprint reaches 2^levels fine voxels beyond its centre, which
    // lies within 2^(levels - 1) of its fine voxels, all inside one fine leaf up to 3 levels; so
    // a value of the fine leaf reaches 1.5 x 2^levels voxels beyond it (a bound for any level).
    return levels <= 0 ? 1.0 : 1.5 * double(1 << levels) + 1.0;
}

std::vector<float> gridMajorants(const openvdb::FloatGrid& grid, const glm::mat4& objectToWorld,
                                 const glm::dvec3& lo, const glm::dvec3& hi, const glm::ivec3& dims,
                                 double margin) {
    std::vector<float> out(std::size_t(dims.x) * dims.y * dims.z, -1.0f);
    const glm::dvec3 cellSize = (hi - lo) / glm::dvec3(dims);
    const glm::dmat4 toWorld(objectToWorld);
    const openvdb::math::Transform& xf = grid.transform();
    // Raises the cells the world box of index box [a, b] (grown by the margin) touches to v.
    auto raise = [&](const openvdb::Vec3d& a, const openvdb::Vec3d& b, float v) {
        glm::dvec3 wlo(1e300), whi(-1e300);
        for (int c = 0; c < 8; ++c) {
            const openvdb::Vec3d p((c & 1) ? b.x() + margin : a.x() - margin,
                                   (c & 2) ? b.y() + margin : a.y() - margin,
                                   (c & 4) ? b.z() + margin : a.z() - margin);
            const openvdb::Vec3d o = xf.indexToWorld(p);
            const glm::dvec3 w = glm::dvec3(toWorld * glm::dvec4(o.x(), o.y(), o.z(), 1.0));
            wlo = glm::min(wlo, w);
            whi = glm::max(whi, w);
        }
        if (glm::any(glm::lessThan(whi, lo)) || glm::any(glm::greaterThan(wlo, hi))) return;
        const glm::ivec3 c0 =
            glm::clamp(glm::ivec3(glm::floor((wlo - lo) / cellSize)), glm::ivec3(0), dims - 1);
        const glm::ivec3 c1 =
            glm::clamp(glm::ivec3(glm::floor((whi - lo) / cellSize)), glm::ivec3(0), dims - 1);
        for (int z = c0.z; z <= c1.z; ++z)
            for (int y = c0.y; y <= c1.y; ++y)
                for (int x = c0.x; x <= c1.x; ++x) {
                    float& m = out[(std::size_t(z) * dims.y + y) * dims.x + x];
                    m = std::max(m, v);
                }
    };
    using Tree = openvdb::FloatTree;
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        float v = -1e30f;
        for (openvdb::Index i = 0; i < Tree::LeafNodeType::SIZE; ++i)
            v = std::max(v, leaf->getValue(i));
        const openvdb::CoordBBox b = leaf->getNodeBoundingBox();
        raise(b.min().asVec3d(), b.max().asVec3d(), std::max(v, 0.0f));
    }
    auto tile = grid.tree().cbeginValueOn();
    tile.setMaxDepth(tile.getLeafDepth() - 1);
    for (; tile; ++tile) {
        openvdb::CoordBBox b;
        tile.getBoundingBox(b);
        raise(b.min().asVec3d(), b.max().asVec3d(), std::max(*tile, 0.0f));
    }
    // Inactive tiles and unallocated space within the leaves' bounds hold the background.
    const float background = grid.background();
    openvdb::CoordBBox b;
    if (background > 0.0f && grid.tree().evalLeafBoundingBox(b))
        raise(b.min().asVec3d(), b.max().asVec3d(), background);
    return out;
}

} // namespace veil::volume
