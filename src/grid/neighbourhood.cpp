#include "grid/neighbourhood.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace veil::volume {

namespace {
int floorDiv(int v, int d) { return v >= 0 ? v / d : -((-v + d - 1) / d); }
} // namespace

double NeighbourhoodMean::at(int x, int y, int z) const {
    x -= origin.x;
    y -= origin.y;
    z -= origin.z;
    if (x < 0 || y < 0 || z < 0 || x >= size.x || y >= size.y || z >= size.z) return 0.0;
    return mean[(std::size_t(z) * size.y + y) * size.x + x];
}

double NeighbourhoodMean::sample(const glm::dvec3& p) const {
    const glm::dvec3 c = (p - (kCell - 1) * 0.5) / double(kCell);
    const glm::dvec3 f0 = glm::floor(c);
    const glm::dvec3 f = c - f0;
    const glm::ivec3 i(f0);
    double v = 0.0;
    for (int k = 0; k < 8; ++k) {
        const glm::ivec3 o(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        const double w =
            (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
        if (w > 0.0) v += w * at(i.x + o.x, i.y + o.y, i.z + o.z);
    }
    return v;
}

NeighbourhoodMean neighbourhoodMean(const openvdb::FloatGrid& grid) {
    NeighbourhoodMean out;
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty()) return out;
    constexpr int n = NeighbourhoodMean::kCell;
    static_assert(openvdb::FloatTree::LeafNodeType::DIM == n);
    out.origin = glm::ivec3(floorDiv(box.min().x(), n), floorDiv(box.min().y(), n),
                            floorDiv(box.min().z(), n));
    const glm::ivec3 last(floorDiv(box.max().x(), n), floorDiv(box.max().y(), n),
                          floorDiv(box.max().z(), n));
    out.size = last - out.origin + 1;
    out.mean.assign(std::size_t(out.size.x) * out.size.y * out.size.z, 0.0f);
    auto cellIndex = [&](const openvdb::Coord& c) {
        const glm::ivec3 k =
            glm::ivec3(floorDiv(c.x(), n), floorDiv(c.y(), n), floorDiv(c.z(), n)) - out.origin;
        return (std::size_t(k.z) * out.size.y + k.y) * out.size.x + k.x;
    };
    // Leaves: one cell each, so the leaves can be summed in parallel.
    std::vector<const openvdb::FloatTree::LeafNodeType*> leaves;
    for (auto it = grid.tree().cbeginLeaf(); it; ++it)
        leaves.push_back(it.getLeaf());
    tbb::parallel_for(std::size_t(0), leaves.size(), [&](std::size_t l) {
        double s = 0.0;
        for (auto v = leaves[l]->cbeginValueOn(); v; ++v)
            s += double(*v);
        out.mean[cellIndex(leaves[l]->origin())] = float(s / double(n * n * n));
    });
    // Active tiles (above the leaf level) cover whole cells.
    auto it = grid.cbeginValueOn();
    it.setMaxDepth(openvdb::FloatGrid::ValueOnCIter::LEAF_DEPTH - 1); // tiles only
    for (; it; ++it) {
        const openvdb::CoordBBox tile = it.getBoundingBox();
        const float v = *it; // a tile's voxels all hold its value
        for (int z = tile.min().z(); z <= tile.max().z(); z += n)
            for (int y = tile.min().y(); y <= tile.max().y(); y += n)
                for (int x = tile.min().x(); x <= tile.max().x(); x += n)
                    out.mean[cellIndex({x, y, z})] = v;
    }
    return out;
}

} // namespace veil::volume
