// A frame range played with overlapped uploads (range_player.h).
#include "sequence/range_player.h"

#include "base/error.h"
#include "frame/renderer.h"

#include <chrono>

namespace veil::sequence {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

} // namespace

nlohmann::json FrameStages::json() const {
    nlohmann::json j = {{"frame", frame},
                        {"wait_ms", waitMs},
                        {"read_ms", readMs},
                        {"convert_ms", convertMs},
                        {"setup_ms", setupMs},
                        {"upload_ms", uploadMs},
                        {"uploaded_ahead", uploadedAhead},
                        {"uploads", uploads},
                        {"uploaded_bytes", uploadedBytes},
                        {"render_ms", renderMs},
                        {"ahead_ms", aheadMs},
                        {"active_voxels", activeVoxels}};
    if (!notes.empty()) j["notes"] = notes;
    return j;
}

RangePlayer::RangePlayer(const scene::AnimatedScene& scene, std::vector<int> frames,
                         const gpu::ContextInfo& context, const frame::RendererOptions& options,
                         std::size_t readAheadBytes, int threads, int max3D, bool overlap)
    : prefetcher_(scene, frames, readAheadBytes, threads, max3D),
      renderers_(context, options, max3D), count_(frames.size()), overlap_(overlap) {}

PlayedFrame RangePlayer::step() {
    VEIL_CHECK(!done(), "no frame left to play");
    PlayedFrame t;
    auto mark = Clock::now();
    PreparedFrame p;
    if (haveAhead_) {
        p = std::move(ahead_);
        haveAhead_ = false;
    } else {
        p = prefetcher_.take();
    }
    t.waitMs = msSince(mark);
    ++next_;
    VEIL_CHECK(p.error.empty(), "{}", p.error);
    t.frame = p.frame;
    t.readMs = p.readMs;
    t.convertMs = p.convertMs;
    t.activeVoxels = p.activeVoxels;
    t.notes = p.notes;
    t.uploadedAhead = p.uploaded;
    if (p.uploaded) {
        t.uploadMs = aheadUploadMs_;
        t.uploads = aheadUploads_;
        t.uploadedBytes = aheadBytes_;
    }

    const std::size_t uploads = renderers_.uploads(), bytes = renderers_.uploadedBytes();
    mark = Clock::now();
    frame::Renderer& renderer = renderers_.next(p);
    t.setupMs = msSince(mark);
    if (!t.uploadedAhead) { // uploaded by next()
        t.uploadMs = renderers_.lastUploadMs();
        t.uploads = renderers_.uploads() - uploads;
        t.uploadedBytes = renderers_.uploadedBytes() - bytes;
    }
    t.renderer = &renderer;

    mark = Clock::now();
    renderer.render();
    t.renderMs = msSince(mark);
    if (overlap_ && !done()) {
        // The GPU renders this frame meanwhile; the next frame's copies queue behind it.
        mark = Clock::now();
        ahead_ = prefetcher_.take();
        haveAhead_ = true;
        if (ahead_.error.empty()) {
            const std::size_t u = renderers_.uploads(), b = renderers_.uploadedBytes();
            if (renderers_.upload(ahead_)) {
                aheadUploadMs_ = renderers_.lastUploadMs();
                aheadUploads_ = renderers_.uploads() - u;
                aheadBytes_ = renderers_.uploadedBytes() - b;
            }
        }
        t.aheadMs = msSince(mark);
    }
    mark = Clock::now();
    glFinish();
    t.renderMs += msSince(mark);
    return t;
}

} // namespace veil::sequence
