// Local majorants of the extinction for the scattered-light cache's GPU bake
// (shaders/volume/cache_bake.comp) and the CPU path tracer (path_tracer.h, which tightens them
// from its dense grid copies, dense_grid.h): a coarse world-space grid over the volumes' box whose
// cells bound the extinction anywhere in them, so that delta and ratio tracking sample their
// tentative collisions cell by cell against the cell's majorant (a DDA through the cells) instead
// of one majorant for all space (piecewise-constant majorants, [Novak18]). Empty cells (majorant 0)
// are crossed without a collision, dense cells keep a tight bound.
//
// A grid's cell majorant is the largest value of every leaf node (8^3 voxels: the bricks of
// the GPU's atlas, fog/gpu_volume.h) or active tile whose trilinear footprint reaches the cell:
// the node's index box grown by `margin` voxels (1: trilinear filtering between voxel centres
// reaches one voxel beyond a node; a grid the GPU coarsened reaches further, coarseningMargin()),
// its values active or not (the atlas stores whole leaves), the background where positive. So
// it bounds every trilinear sample of the grid and of its GPU textures (whose R16F values may
// round up by 2^-11 of themselves: the bake scales the majorants by a little more).
#pragma once

#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <vector>

namespace veil::volume {

struct MajorantGrid {
    glm::dvec3 lo{0.0}, hi{0.0}; // world box; cell c covers lo + [c, c + 1) / dims x (hi - lo)
    glm::ivec3 dims{0};
    std::vector<float> values; // x fastest; extinction (density_scale x the grid's value)

    // The cell holding world point p (clamped to the grid).
    glm::ivec3 cellOf(const glm::dvec3& p) const;
    float at(const glm::ivec3& cell) const {
        return values[(std::size_t(cell.z) * dims.y + cell.y) * dims.x + cell.x];
    }
};

// Cells of about one leaf node (`voxelsPerCell`, 8, voxels) of the finest grid per axis over
// [lo, hi], at most kMajorantMaxCells per axis, at least 1.
inline constexpr int kMajorantMaxCells = 128;
glm::ivec3 majorantDims(const scene::Scene& scene,
                        const std::vector<openvdb::FloatGrid::ConstPtr>& grids,
                        const glm::dvec3& lo, const glm::dvec3& hi, double voxelsPerCell = 8.0);

// The footprint margin, in voxels of the original grid, of a GPU copy coarsened `levels` times
// (grid/grid_conversion.cpp coarsen(): each level takes the mean of 2^3 voxels, its centre
// half a voxel off): 1 for none.
double coarseningMargin(int levels);

// Per cell over `dims` on [lo, hi] the largest unscaled value of `grid` (placed in the world by
// its transform, then `objectToWorld`) that trilinear filtering can reach in the cell; -1 where
// no node of the grid reaches it (and the background is not positive).
std::vector<float> gridMajorants(const openvdb::FloatGrid& grid, const glm::mat4& objectToWorld,
                                 const glm::dvec3& lo, const glm::dvec3& hi, const glm::ivec3& dims,
                                 double margin);

} // namespace veil::volume
