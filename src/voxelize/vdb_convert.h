// Slice map -> OpenVDB grids (BoolGrid mask, FloatGrid density) and .vdb files.
//
// Transforms
//   orthographic, axis-aligned, uniform slicing (makeOrthoGrid): cell (x, y, s) is voxel
//     (x, y, s) and the transform is linear: per-axis voxel size, origin at cell (0,0,0)'s
//     centre, so index-space voxel centres are the slice map's cell centres in world space.
//   perspective grids, local slicing, rotated ortho cameras: cells are not a lattice in world
//     space, so the map is resampled into a world-aligned grid over the grid camera's world
//     bounds (frustum corners): voxel size `resampleVoxel`, or (default) the cube root of
//     bounds volume / cell count (as many voxels as cells); a voxel is on iff the slice map
//     is occupied at its centre (SliceMap::occupied).
//   density: 1 on set voxels; with smoothing > 0 the topology is dilated by ceil(2 width)
//     voxels and openvdb::tools::Filter::gaussian(width) turns it into a soft fog density.
#pragma once

#include "voxelize/slice_map.h"

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>
#include <string>

namespace veil::voxelize {

struct VdbOptions {
    double smoothing = 0.0; // gaussian half-width in voxels; 0 = binary density
    // Refuse smoothing whose estimated work (voxel updates) is past this, before any of it
    // runs; 0 = no limit. 5e9 is about 25 s on 2 cores.
    double smoothingWorkLimit = 5e9;
    double resampleVoxel = 0.0; // world voxel size for resampled grids; 0 = automatic
    std::function<void(double)> progress;
};

struct VdbGrids {
    openvdb::BoolGrid::Ptr mask;        // name "mask"
    openvdb::FloatGrid::Ptr density;    // name "density"
    glm::ivec3 dims{0};                 // index box [0, dims)
    glm::dvec3 origin{0.0}, voxel{0.0}; // world centre of voxel (0,0,0), voxel size per axis
    bool resampled = false;
    std::string note; // how the transform was made (for reports)
};

// True for an axis-aligned orthographic grid with uniform slicing (lattice cells).
bool isLatticeGrid(const SliceMap& map);
VdbGrids toVdb(const SliceMap& map, const VdbOptions& options = {});
// Writes both grids through a temporary file renamed into place (base/atomic_file.h).
void writeVdb(const std::filesystem::path& path, const VdbGrids& grids);

} // namespace veil::voxelize
