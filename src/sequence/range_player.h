// Playing a frame range through one renderer (prefetch.h RangeRenderer) with the next frame's
// upload overlapping the current frame's render: step() renders a frame, and before waiting
// for the GPU to finish it takes the next frame from the read-ahead and, when that frame keeps
// the renderer, uploads its volumes (staging buffer and texture copies queued behind the
// frame's commands). Used by `veil render --frames` (range_render.h), veil-seqbench and the
// Python module's Renderer.frames().
#pragma once

#include "sequence/prefetch.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace veil::sequence {

// What one played frame cost, stage by stage, as `veil render --frames --report`, veil-seqbench
// and the Python module's Renderer.frames() report it (json(): the names docs/sequences.md
// gives).
struct FrameStages {
    int frame = 0;
    double waitMs = 0.0;    // waiting for the workers before the frame could start
    double readMs = 0.0;    // on a worker: resolving and reading the grids
    double convertMs = 0.0; // on a worker: converting them into the GPU's arrays
    double uploadMs = 0.0;  // this frame's volume upload calls (render thread; during the
                            // previous frame's render when `uploadedAhead`)
    bool uploadedAhead = false;
    double setupMs = 0.0;  // the renderer built, or the camera and lights switched (and the
                           // upload when not ahead)
    double renderMs = 0.0; // render() and glFinish, without the next frame's upload calls
    double aheadMs = 0.0;  // taking and uploading the next frame while the GPU renders
    std::size_t uploads = 0, uploadedBytes = 0; // volume uploads of this frame
    std::uint64_t activeVoxels = 0;
    std::vector<std::string> notes;

    nlohmann::json json() const;
};

struct PlayedFrame : FrameStages {
    frame::Renderer* renderer = nullptr; // the image is complete (glFinish), not read back
};

class RangePlayer {
public:
    // `overlap` false: each frame uploads its volumes right before its render (to compare).
    RangePlayer(const scene::AnimatedScene& scene, std::vector<int> frames,
                const gpu::ContextInfo& context, const frame::RendererOptions& options,
                std::size_t readAheadBytes, int threads, int max3D, bool overlap = true);
    RangePlayer(const RangePlayer&) = delete;
    RangePlayer& operator=(const RangePlayer&) = delete;

    bool done() const { return next_ >= count_; }
    // Renders the next frame of the range. Throws veil::Error naming the file when the frame
    // could not be prepared (the frames before it were rendered).
    PlayedFrame step();
    const RangeRenderer& renderers() const { return renderers_; }
    std::size_t peakReadAheadBytes() const { return prefetcher_.peakBytes(); }

private:
    FramePrefetcher prefetcher_;
    RangeRenderer renderers_;
    std::size_t count_, next_ = 0;
    bool overlap_;
    bool haveAhead_ = false;
    PreparedFrame ahead_; // the next frame, taken (and uploaded when it could be) early
    double aheadUploadMs_ = 0.0;
    std::size_t aheadUploads_ = 0, aheadBytes_ = 0;
};

} // namespace veil::sequence
