// Optical depth statistics of a density grid along a view, for choosing a density scale
// from the data rather than from its maximum alone.
#pragma once

#include <openvdb/openvdb.h>

namespace veil::vdb {

struct OpticalDepthStats {
    double median = 0.0; // median over the rays that meet density (> 0), unscaled
    int raysWithDensity = 0;
    int rays = 0;
};

// Parallel rays along `direction` (any length) through the grid's active world box, on a
// `raysPerSide` x `raysPerSide` lattice over the box's projection onto the plane normal to the
// direction; each integrates the trilinearly interpolated density (negative values count as 0)
// with the midpoint rule at half a voxel (at most 1024 steps per ray), from a voxel before the
// box to a voxel after it. Returns the median of
// the non-zero optical depths, so empty space around the volume does not pull it to zero.
OpticalDepthStats medianOpticalDepth(const openvdb::FloatGrid& grid, openvdb::Vec3d direction,
                                     int raysPerSide = 48);

} // namespace veil::vdb
