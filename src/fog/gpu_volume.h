// A density grid on the GPU, following its active voxels rather than its bounding box:
// active leaf nodes (8^3) are packed into a 3D brick atlas (R16F, 10^3 per brick: one voxel of
// apron on every side so hardware trilinear filtering is correct across bricks) and a 3D
// indirection texture over the leaf grid maps a leaf to its brick (0 = empty: the marcher
// skips the whole leaf). Small grids use one dense 3D texture instead.
//
// Leaves are dilated by one toward -x, -y, -z: a sample whose lower trilinear corner lies in an
// empty leaf still reaches the values of the non-empty neighbour through that leaf's brick.
#pragma once

#include "gpu/objects.h"
#include "grid/gpu_volume_stats.h"
#include "grid/grid_conversion.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace veil::volume {

static_assert(std::is_same_v<openvdb::Index64, std::uint64_t>);

// A 3D texture of `texels` (floats in `format`, x fastest) stored as `internalFormat`, with
// trilinear filtering and `wrap` on every axis (GL_CLAMP_TO_BORDER: the default border, 0).
gpu::Texture makeFilteredTexture3D(const glm::ivec3& size, GLenum internalFormat, GLenum format,
                                   const float* texels, GLenum wrap = GL_CLAMP_TO_EDGE);

class GpuVolume {
public:
    GpuVolume(const GpuVolume&) = delete;
    GpuVolume& operator=(const GpuVolume&) = delete;
    ~GpuVolume();
    // `objectToWorld` is the scene entry's transform, applied after the grid's own
    // index-to-world transform (which must be affine). Before allocating anything the upload is
    // planned: a grid over the budget, over GL_MAX_3D_TEXTURE_SIZE or with an indirection table
    // over 2^25 entries is coarsened (or refused with refuseOverBudget), with the estimate and
    // the limit in the message; index coordinates beyond +-2^24 are refused. Throws
    // veil::Error.
    GpuVolume(openvdb::FloatGrid::ConstPtr grid, const glm::mat4& objectToWorld,
              const GpuVolumeOptions& options = {});
    // Uploads a conversion made earlier (grid_conversion.h, on any thread): the same textures
    // as the constructor above makes from the grid the conversion was made from.
    GpuVolume(const GridConversion& converted, const glm::mat4& objectToWorld);
    // The next frame of a range: the same as constructing from `converted`, but the data,
    // channel and indirection textures are kept where their allocated size (the conversion's
    // rounded up, allocatedSize()) is unchanged, and only their texels are uploaded.
    //
    // Frames held on the GPU: a conversion with a key (GridConversion::gpuKey) keeps its
    // textures under that key, with the other held frames, while their texture bytes (allocated
    // sizes) fit GridConversion::gpuHoldBytes. A conversion whose key is held shows those
    // textures again: nothing is uploaded (stats().reshown counts it) and the image is the
    // same as after its upload. Otherwise the least recently shown frames are dropped until
    // the new one fits, and the new frame takes the textures of a dropped one (reallocated
    // only where its size differs); a frame larger than the budget alone, or without a key,
    // is shown but not held. With gpuHoldBytes 0 every frame uploads into the one set of
    // textures, as without keys.
    void replace(const GridConversion& converted, const glm::mat4& objectToWorld);

    // Of the shown frame, with the held frames and upload counters of the volume.
    const GpuVolumeStats& stats() const { return stats_; }
    const gpu::Texture& data() const { return shown_->data; } // atlas or dense R16F
    // The conversion's second channel (emission), same layout as data(); null if none. R16F
    // (1 component) or RGBA16F (4: RGB and 0).
    const gpu::Texture& channel() const { return shown_->channel; }
    int channelComponents() const { return shown_->channelComponents; }
    const gpu::Texture& indirection() const { return shown_->indirection; } // R32UI (bricks)
    // The mean density per 8^3-voxel cell (grid/neighbourhood.h), R32F, trilinear, zero
    // border; cell (0,0,0) of the texture is cell neighbourhoodOrigin() of the grid. Null unless
    // the conversion had GpuVolumeOptions::neighbourhood.
    const gpu::Texture& neighbourhood() const { return shown_->neighbourhood; }
    glm::ivec3 neighbourhoodOrigin() const { return shown_->neighbourhoodOrigin; }
    const glm::mat4& worldToIndex() const { return worldToIndex_; }
    const glm::mat4& indexToWorld() const { return indexToWorld_; }
    // Index-space bounds of the stored data, voxel centres at integer coordinates.
    glm::vec3 indexMin() const { return shown_->indexMin; }
    glm::vec3 indexMax() const { return shown_->indexMax; }
    glm::ivec3 leafOrigin() const { return shown_->leafOrigin; } // leaf (0,0,0) of the table
    glm::ivec3 bricksPerAxis() const { return shown_->bricksPerAxis; }
    // World-space axis-aligned bounds.
    void worldBounds(glm::vec3& lo, glm::vec3& hi) const;
    float voxelSize() const { return voxelSize_; } // world units (largest axis)

    // The size a texture holding `texels` is allocated with, so that the frames of a range,
    // whose sizes drift, mostly share one allocation: the brick atlas (`atlas`) gets up to 1/8
    // more layers of bricks in z (at least a multiple of 2 layers; x and y, the atlas's side,
    // change rarely), a dense box or indirection table up to 1/8 more texels per axis (a
    // multiple of 8), within `max3D`. A function of the size alone: a frame's textures have one
    // size however they were reached, and the shaders, which address the data by the texture's
    // size, sample it identically. The texels past the data are never read. The volume's
    // GpuVolumeStats::gpuBytes counts the data, not this headroom.
    static glm::ivec3 allocatedSize(const glm::ivec3& texels, bool atlas, int max3D);

private:
    // One frame's textures and the values the shaders take with them.
    struct Frame {
        std::string key; // held under it; empty: not held (the next frame takes the textures)
        std::uint64_t lastShown = 0;
        std::size_t bytes = 0; // allocated texture bytes
        GpuVolumeStats stats;  // the conversion's
        gpu::Texture data{gpu::NoCreate}, indirection{gpu::NoCreate}, channel{gpu::NoCreate};
        gpu::Texture neighbourhood{gpu::NoCreate};
        glm::ivec3 neighbourhoodOrigin{0};
        int channelComponents = 0;
        glm::mat4 gridToWorld{1.0f}; // the conversion's index-to-world
        glm::vec3 indexMin{0.0f}, indexMax{0.0f};
        glm::ivec3 leafOrigin{0}, bricksPerAxis{0};
    };

    void upload(const GridConversion& converted, const glm::mat4& objectToWorld);
    // The textures (kept where their size fits) and values of `converted` in `f`, its texels
    // read from `values`, `channel` and `table` (client memory, or offsets into the bound
    // unpack buffer).
    void upload(Frame& f, const GridConversion& converted, const void* values, const void* channel,
                const void* table);
    // `f` shown with `objectToWorld`; the statistics updated.
    void show(Frame* f, const glm::mat4& objectToWorld);
    // The frame `converted` is uploaded into: held frames dropped (least recently shown first)
    // until it fits its budget, their textures reused for it.
    Frame* frameFor(const GridConversion& converted);
    // Copies `bytes` to the staging buffer (a pixel unpack buffer, persistently mapped and grown
    // when needed) at the next free offset, which it returns.
    std::size_t stage(const void* data, std::size_t bytes);
    // The same for `texels` as half floats (the 16-bit textures' own format): `half` copied
    // when the conversion made it (GridConversion::halfValues), else converted here.
    std::size_t stageHalf(const std::vector<float>& texels, const std::vector<std::uint16_t>& half);

    GpuVolumeStats stats_;
    std::vector<std::unique_ptr<Frame>> frames_; // held frames and the shown one
    Frame* shown_ = nullptr;
    std::uint64_t shownCount_ = 0;
    std::size_t uploads_ = 0, uploadedBytes_ = 0, reshown_ = 0;
    gpu::Buffer staging_{gpu::NoCreate};
    void* stagingMap_ = nullptr;
    std::size_t stagingUsed_ = 0;
    GLsync uploaded_ = nullptr; // the last upload's reads from the staging buffer
    glm::mat4 worldToIndex_{1.0f}, indexToWorld_{1.0f};
    float voxelSize_ = 1.0f;
};

} // namespace veil::volume
