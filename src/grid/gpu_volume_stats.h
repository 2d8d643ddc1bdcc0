// The options and statistics of a GpuVolume (fog/gpu_volume.h), without OpenVDB: headers
// that only pass them on (fog/fog_pass.h, included by the renderer and most tests) need not
// parse openvdb/openvdb.h (about 3 s of compile time per translation unit).
#pragma once

#include <cstddef>
#include <cstdint>

namespace veil::volume {

struct GpuVolumeOptions {
    std::size_t budgetBytes = std::size_t(1024) << 20;
    bool refuseOverBudget = false; // false: coarsen (voxel size x2 until it fits) with a warning
    std::size_t denseVoxelLimit = std::size_t(96) * 96 * 96; // bounding boxes up to this: dense
    // Also the mean density per 8^3-voxel cell (grid/neighbourhood.h), for the depth-aware
    // octaves (render.fog_octave_radius > 0): an array of the indirection table's size.
    bool neighbourhood = false;
};

struct GpuVolumeStats {
    std::size_t gpuBytes = 0;  // textures of this volume (atlas or dense, indirection)
    std::size_t gridBytes = 0; // openvdb's own memory for the grid
    std::size_t bricks = 0;    // 0 for the dense path
    bool dense = false;
    int coarsened = 0;              // times the voxel size was doubled to fit the budget
    std::uint64_t activeVoxels = 0; // openvdb::Index64 (gpu_volume.h checks)
    // Not the conversion's but the GpuVolume's (fog/gpu_volume.h): the frames it holds on the
    // GPU and their texture bytes (allocated sizes, the shown frame included), and since it was
    // made: uploads from host memory with their bytes as sent, and frames shown again from
    // the held textures (no upload).
    std::size_t heldFrames = 0, heldBytes = 0;
    std::size_t uploads = 0, uploadedBytes = 0, reshown = 0;
};

} // namespace veil::volume
