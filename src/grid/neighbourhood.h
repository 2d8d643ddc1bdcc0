// The mean density around a point, for the depth-aware multiple-scattering octaves of the fog
// (render.fog_octave_radius, docs/volumes.md "Multiple scattering by octaves"): the grid's
// active values summed over cells of 8^3 voxels aligned to OpenVDB's leaf nodes (inactive
// voxels count 0), divided by 512, and interpolated trilinearly between the cells' centres
// (index 8k + 3.5); cells outside the array read 0. The GPU samples the same array as an R32F
// texture with hardware filtering and a zero border (fog/gpu_volume.h), the CPU fog
// reference through sample(): both compute one model.
#pragma once

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <vector>

namespace veil::volume {

struct NeighbourhoodMean {
    static constexpr int kCell = 8; // voxels per cell and axis
    glm::ivec3 origin{0};           // cell coordinate of element 0 (index / 8, floored)
    glm::ivec3 size{0};             // cells per axis
    std::vector<float> mean;        // size.x * size.y * size.z, x fastest

    // The mean density at index-space point p (voxel centres at integers), trilinear between
    // the cells' centres.
    double sample(const glm::dvec3& p) const;
    // Cell value, 0 outside the array.
    double at(int x, int y, int z) const;
};

// The cell means of `grid`'s active voxels and tiles (TBB over leaf nodes).
NeighbourhoodMean neighbourhoodMean(const openvdb::FloatGrid& grid);

} // namespace veil::volume
