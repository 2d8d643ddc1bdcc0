// Reading a frame range's grids ahead of the frame being rendered: worker threads resolve each
// frame's scene (scene/timeline.h), read and sanitize its volumes' grids (OpenVDB decoding) and
// convert them into the GPU's arrays (grid/grid_conversion.h, itself multithreaded with TBB):
// the whole CPU side of a frame, in frame order, while the caller renders earlier frames. Frames
// are handed out in order; a worker does not start a frame more than one ahead of the caller
// while the grids read and not yet taken use more than the memory budget.
#pragma once

#include "frame/frame_setup.h"
#include "gpu/context.h"
#include "grid/grid_preload.h"
#include "scene/timeline.h"

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace veil::frame {
class Renderer;
}
namespace veil::volume {
struct GridConversion;
}

namespace veil::sequence {

struct PreparedFrame {
    int frame = 0;
    scene::Scene scene;                       // the scene at this frame
    std::vector<volume::PreloadedGrid> grids; // its file volumes' grids
    std::vector<std::string> notes;           // held missing files
    std::string error;      // set: the frame could not be prepared (missing, corrupt)
    double readMs = 0.0;    // wall time of resolving and reading on the worker
    double convertMs = 0.0; // wall time of the GPU conversion on the worker
    std::size_t bytes = 0;  // memory of its grids and their conversions
    std::uint64_t activeVoxels = 0;
    bool uploaded = false; // RangeRenderer::upload() put its volumes on the GPU already
};

// GPU conversions of the grids that do not change with the frame (readStaticGrids()), made
// once and shared by every frame whose conversion options match. Thread-safe.
class StaticConversions {
public:
    // The conversion of static grid `grid` (with `channel`, a temperature grid, as its
    // emission channel when not null) with `options` for `max3D`, made on first use (held on
    // the GPU under `key` within `holdBytes`: GridConversion::gpuKey).
    std::shared_ptr<const volume::GridConversion> get(const openvdb::FloatGrid& grid,
                                                      const openvdb::FloatGrid::Ptr& channel,
                                                      const volume::GpuVolumeOptions& options,
                                                      int max3D, const std::string& key = {},
                                                      std::size_t holdBytes = 0);
    std::size_t conversions() const; // made so far (tests)

private:
    struct Item {
        const openvdb::FloatGrid* grid;
        const openvdb::FloatGrid* channel;
        volume::GpuVolumeOptions options;
        int max3D;
        std::shared_ptr<const volume::GridConversion> converted;
    };
    mutable std::mutex mutex_;
    std::vector<Item> items_;
};

// Everything a frame needs before the render thread takes it: the scene at `frame`, its file
// volumes' grids (those of `staticGrids` shared, the rest read; a volume's temperature or scalar
// emission grid with its density, from the same read of the file) and, with `max3D` > 0, their
// GPU conversions (a static grid's from `conversions` when given, so converted once). Errors (a
// missing or corrupt file) are kept in PreparedFrame::error.
PreparedFrame prepareFrame(const scene::AnimatedScene& scene, int frame,
                           const std::vector<volume::PreloadedGrid>& staticGrids, int max3D,
                           StaticConversions* conversions = nullptr);

// Whether a renderer built on `current` can show `next` by replacing its volumes' data
// (frame::Renderer::replaceVolumes): the same structure (the same volumes, lights and cameras,
// file volumes only, no baked scattered-light cache) and, among `grids`, a conversion made
// ahead for `max3D` of every grid volume of `next` (with its temperature channel), put into
// `out` in scene order.
bool replaceableBy(const scene::Scene& current, const scene::Scene& next,
                   const std::vector<volume::PreloadedGrid>& grids, int max3D,
                   std::vector<const volume::GridConversion*>& out);

// File volumes that do not change with the frame, read once (errors thrown at once).
std::vector<volume::PreloadedGrid> readStaticGrids(const scene::AnimatedScene& scene);

class FramePrefetcher {
public:
    // `threads` workers (at least 1); `budgetBytes` bounds the grids read ahead. `max3D` > 0:
    // the grids are also converted for a GPU with that GL_MAX_3D_TEXTURE_SIZE, with the options
    // the fog pass will use (render.volume_budget_mib, volume_over_budget); 0: read only.
    FramePrefetcher(const scene::AnimatedScene& scene, std::vector<int> frames,
                    std::size_t budgetBytes, int threads = 2, int max3D = 0);
    ~FramePrefetcher(); // stops the workers (frames in progress finish first)
    FramePrefetcher(const FramePrefetcher&) = delete;
    FramePrefetcher& operator=(const FramePrefetcher&) = delete;

    // The next frame in order (blocks until it is ready); the caller owns it.
    PreparedFrame take();
    bool done() const { return next_ >= frames_.size(); }
    // Most bytes of grids held read ahead at once (the budget test).
    std::size_t peakBytes() const;

private:
    void work();

    const scene::AnimatedScene& scene_;
    std::vector<int> frames_;
    std::size_t budget_;
    int max3D_ = 0;
    // Grids of file volumes that are not sequences, read once and shared by every frame.
    std::vector<volume::PreloadedGrid> staticGrids_;
    StaticConversions conversions_;
    mutable std::mutex mutex_;
    std::condition_variable ready_, space_;
    std::vector<std::unique_ptr<PreparedFrame>> slots_; // by position in frames_
    std::size_t claimed_ = 0, next_ = 0, heldBytes_ = 0, peakBytes_ = 0;
    bool stop_ = false;
    std::vector<std::thread> workers_;
};

// Frees frames' grids and conversions on a thread of its own: a frame of 30 M voxels holds
// hundreds of MB of trees and arrays, whose release (OpenVDB's node deletion, the pages given
// back) would otherwise take the render thread's time once the upload copied them.
class GridReleaser {
public:
    GridReleaser();
    ~GridReleaser(); // frees what is left, then stops
    GridReleaser(const GridReleaser&) = delete;
    GridReleaser& operator=(const GridReleaser&) = delete;
    void release(std::vector<volume::PreloadedGrid>&& grids); // `grids` is left empty

private:
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::vector<volume::PreloadedGrid>> queue_;
    bool stop_ = false;
    std::thread thread_;
};

// One renderer for a range's frames: the first frame builds it; a later frame with the same
// structure (the same volumes, lights and cameras; every grid volume converted ahead for this
// GPU, with its temperature channel) only replaces the volumes' data, the camera and the
// lights (frame::Renderer::replaceVolumes), keeping programs, targets, shadow resources and
// the other stages; another structure builds a new renderer. The image equals a renderer
// built for the frame alone.
class RangeRenderer {
public:
    RangeRenderer(const gpu::ContextInfo& context, frame::RendererOptions options, int max3D);
    ~RangeRenderer();
    RangeRenderer(const RangeRenderer&) = delete;
    RangeRenderer& operator=(const RangeRenderer&) = delete;

    // The renderer for frame `p` (its scene and grids are taken; p.grids is emptied).
    frame::Renderer& next(PreparedFrame& p);
    // The first half of next() for a frame that can reuse the renderer, called while the
    // current frame is still rendering (after its render(), before its image is read back):
    // uploads p's volumes into the renderer's textures (Renderer::uploadVolumes; the copies
    // run on the GPU after the current frame's commands) and marks p uploaded; next(p) then
    // only switches the camera and lights. False (nothing done) when p needs a new renderer.
    bool upload(PreparedFrame& p);
    int built() const { return built_; }   // renderers built so far
    int reused() const { return reused_; } // frames that replaced volumes only
    // Volume uploads from host memory so far: grid volumes built or replaced (a frame held on
    // the GPU and shown again is none: fog/gpu_volume.h), their texels' bytes as sent (half
    // floats, the indirection table, the neighbourhood means), and the wall time of the last
    // frame's upload calls (ms; building: the whole construction).
    std::size_t uploads() const { return uploads_; }
    std::size_t uploadedBytes() const { return uploadedBytes_; }
    double lastUploadMs() const { return lastUploadMs_; }

private:
    gpu::ContextInfo context_;
    frame::RendererOptions options_;
    int max3D_;
    scene::Scene current_; // the scene the renderer references, updated in place
    std::unique_ptr<frame::Renderer> renderer_;
    std::vector<const volume::GridConversion*> conversions_;
    int built_ = 0, reused_ = 0;
    std::size_t uploads_ = 0, uploadedBytes_ = 0;
    double lastUploadMs_ = 0.0;
    GridReleaser releaser_; // last: it frees the frames' grids before the renderer goes
};

} // namespace veil::sequence
