// Rendering a scene's frames into numbered images in one process and one GL context: grids of
// the next frames are read and converted on worker threads (prefetch.h) while the current
// frame renders, and the next frame's volumes are uploaded behind it (range_player.h);
// every image is written atomically (temporary file + rename), so an interrupted range leaves
// complete frames only, and a resumed one skips the frames whose image is complete.
#pragma once

#include "frame/frame_setup.h"
#include "gpu/context.h"
#include "scene/timeline.h"
#include "sequence/range_player.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace veil::sequence {

// Where frame `frame` goes: the output's frame pattern (scene/animation.h: out.####.exr,
// out.%04d.png, out.$F4.exr, out.#.png) filled in; a name without a pattern is taken as it is
// when `single` (one frame), else refused.
std::filesystem::path outputFor(const std::string& output, int frame, bool single);

// Whether `path` holds a complete image of width x height (readable to its last pixel).
bool outputComplete(const std::filesystem::path& path, int width, int height);

struct RangeProgress {
    int done = 0, total = 0; // frames finished (rendered or skipped) of the range
    int frame = 0;           // the frame just finished
    double framesPerSecond = 0.0, secondsLeft = 0.0;
};

struct RangeJob {
    std::filesystem::path scenePath; // for the EXR metadata
    std::vector<int> frames;
    std::string output; // with a frame pattern unless one frame
    bool resume = false;
    bool half = false; // EXR: half-float channels
    frame::RendererOptions options;
    int threads = 2; // workers reading grids ahead
    std::function<void(const RangeProgress&)> progress;
    const std::atomic<bool>* stop = nullptr; // set (a signal): stop after the current frame
};

// A frame of the range: its stages (a skipped frame has only `frame`), the image written.
struct FrameTimes : FrameStages {
    std::filesystem::path output;
    bool skipped = false; // --resume: complete already
    double gpuMs = 0.0;   // sum of the pass timers
    double writeMs = 0.0; // read-back and writing the image
};

struct RangeResult {
    std::vector<FrameTimes> frames; // rendered or skipped, in order
    bool interrupted = false;       // stopped by job.stop before the end
    double wallSeconds = 0.0;
    std::size_t peakReadAheadBytes = 0;
    nlohmann::json json() const; // for the report
};

// Checks every frame's files before anything renders (a missing one: veil::Error naming it),
// then renders the frames. A frame whose grid cannot be read throws veil::Error naming the
// file; the frames before it stay written.
RangeResult renderRange(const scene::AnimatedScene& scene, const RangeJob& job,
                        const gpu::ContextInfo& context);

} // namespace veil::sequence
