// The CPU side of putting a density grid on the GPU (fog/gpu_volume.h): the upload is planned
// against the budget and the texture size limit (coarsening the grid until it fits), then the
// grid is converted to the arrays the textures are made of: a dense box of voxels, or the brick
// atlas (active leaves with a one-voxel apron) and its indirection table. No GL: it runs on any
// thread (src/sequence converts the next frames on worker threads while the GPU renders) and is
// multithreaded with TBB over bricks (dense: over z slices), as OpenVDB's own tools are. The
// result does not depend on the number of threads (each texel is written by one task).
#pragma once

#include "grid/gpu_volume_stats.h"
#include "grid/neighbourhood.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace veil::volume {

struct GridConversion {
    std::string name;                 // the grid's
    GpuVolumeStats stats;             // gpuBytes, bricks, dense, coarsened, activeVoxels, gridBytes
    std::string coarsenedBecause;     // why it was coarsened (empty: it was not)
    glm::mat4 indexToWorld{1.0f};     // the (possibly coarsened) grid's own transform
    glm::ivec3 dataSize{0};           // texels of the dense texture or of the atlas
    std::vector<float> values;        // dataSize.x * .y * .z, x fastest
    glm::ivec3 tableSize{0};          // leaves of the indirection table (bricks only)
    std::vector<std::uint32_t> table; // brick index + 1 per leaf, 0 = empty
    glm::vec3 indexMin{0.0f}, indexMax{0.0f};
    glm::ivec3 leafOrigin{0}, bricksPerAxis{0};
    // indexToWorld in double: the grid's (or its coarsened copy's) transform (addChannel()).
    openvdb::math::Transform::ConstPtr transform;
    // A second texture in the same layout (addChannel()): channelComponents (1, or 4: RGB and
    // an unused 0) floats per texel, or empty.
    std::vector<float> channel;
    int channelComponents = 0;
    // `values` and `channel` as the textures store them, IEEE half floats (packHalf(), on the
    // thread that converts); empty: not made, the upload converts them itself.
    std::vector<std::uint16_t> halfValues, halfChannel;
    // The mean density of every 8^3-voxel cell (the depth-aware octaves' texture, R32F), with
    // GpuVolumeOptions::neighbourhood only (else empty).
    NeighbourhoodMean neighbourhood;
    // Holding the uploaded frame on the GPU (GpuVolume keeps several frames' textures, least
    // recently shown dropped first): `gpuKey` names the data (file, grid, channel, options;
    // sequence/prefetch.cpp makes it), empty: not held; `gpuHoldBytes` is the texture memory
    // the volume may hold frames in (render.sequence_gpu_cache_mib; 0: none).
    std::string gpuKey;
    std::size_t gpuHoldBytes = 0;

    // Host memory the arrays hold.
    std::size_t bytes() const {
        return (values.size() + channel.size() + neighbourhood.mean.size()) * sizeof(float) +
               (halfValues.size() + halfChannel.size()) * 2 + table.size() * 4;
    }
};

// Plans and converts `grid` for a GPU whose GL_MAX_3D_TEXTURE_SIZE is `max3D`. `threads` > 0
// runs in a TBB arena of that many threads (1: single-threaded), 0 in the caller's arena.
// Throws veil::Error (empty grid, over the budget with refuseOverBudget, non-affine transform,
// index range) with the reasons gpu_volume.h lists.
GridConversion convertGrid(const openvdb::FloatGrid& grid, const GpuVolumeOptions& options,
                           int max3D, int threads = 0);

// Fills `converted.channel` with `grids` (one, or three: R, G, B) at the position of every texel
// of the conversion's layout (the bricks of its indirection table, or the dense box): the
// emission channel of a volume (temperature or emission grid) beside its density. A grid with
// the conversion's voxels (same voxel size and axes, origin whole voxels apart; the usual case
// of a simulation's grids, not a coarsened conversion) is copied leaf by leaf, the value of each
// texel's voxel; any other is sampled (trilinear, in world space) at every texel. Adds its
// half-float texels (R16F, or RGBA16F for three) to stats.gpuBytes. TBB-parallel like
// convertGrid().
void addChannel(GridConversion& converted, const std::vector<openvdb::FloatGrid::Ptr>& grids);

// IEEE half floats of `n` floats, rounded to nearest even, as GL converts GL_FLOAT pixels for a
// 16-bit float texture (Mesa too): with F16C where the CPU has it (8 at a time), else Imath's
// conversion.
void toHalf(const float* in, std::uint16_t* out, std::size_t n);

// Fills `converted.halfValues` and `halfChannel` (toHalf(), TBB-parallel): the texels ready to
// copy into the upload's staging buffer, made on the converting thread (a range's prefetch
// workers) instead of the render thread.
void packHalf(GridConversion& converted);

// Bytes the GPU representation of `grid` would take (without building it; a lower bound for
// grids far over the budget, whose tiles are not enumerated).
std::size_t estimateGpuBytes(const openvdb::FloatGrid& grid, const GpuVolumeOptions& options);

} // namespace veil::volume
