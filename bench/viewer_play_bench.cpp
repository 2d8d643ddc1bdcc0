// veil-bench --viewer-play (viewer_play_bench.h).
#include "viewer_play_bench.h"

#include "bench_stats.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "fog/fog_pass.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "viewer/session/timeline_player.h"
#include "viewer/session/view_session.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <thread>

namespace veil::bench {

namespace {

struct VolumeCounts {
    std::size_t uploads = 0, reshown = 0;
};

VolumeCounts volumeCounts(const session::ViewSession& session) {
    VolumeCounts c;
    if (const volume::FogPass* fog = session.renderer().fog())
        for (const volume::GpuVolumeStats& v : fog->stats()) {
            c.uploads += v.uploads;
            c.reshown += v.reshown;
        }
    return c;
}

// One phase: `count` new frames shown, each as soon as the timeline has it. Per shown frame:
// `wait` (UI frames that found the target not ready, with the time they took), `show`
// (TimelinePlayer::update showing it: the volumes replaced, uploaded or taken from the GPU),
// `render` (ViewSession::renderFrame + glFinish) and the frame's whole wall time.
struct Phase {
    std::vector<double> wait, show, render, frame;
    double wallMs = 0.0;
    VolumeCounts before, after;
};

Phase play(session::ViewSession& session, session::TimelinePlayer& player, int count,
           bool backwards, double timeoutS) {
    Phase p;
    p.before = volumeCounts(session);
    const auto start = Clock::now();
    for (int i = 0; i < count; ++i) {
        const auto t0 = Clock::now();
        if (backwards) player.step(-1);
        double waited = 0.0;
        for (;;) {
            const int shown = player.shown();
            const auto u = Clock::now();
            // Scripted: one frame further once the last was shown (forwards), so every frame
            // of the range is shown, none skipped by the clock.
            player.update(session, 0.0, !backwards);
            const double ms = msSince(u);
            if (player.shown() != shown) {
                p.show.push_back(ms);
                break;
            }
            VEIL_CHECK(player.status().find(" failed (") == std::string::npos, "--viewer-play: {}",
                       player.status());
            VEIL_CHECK(msSince(start) < 1e3 * timeoutS, "--viewer-play: no frame after {} s ({})",
                       timeoutS, player.status());
            waited += ms;
            std::this_thread::sleep_for(std::chrono::microseconds(200));
            waited += 0.2;
        }
        p.wait.push_back(waited);
        const auto r = Clock::now();
        VEIL_CHECK(session.renderFrame(false), "--viewer-play: frame {} failed: {}", player.shown(),
                   session.lastError());
        glFinish();
        p.render.push_back(msSince(r));
        p.frame.push_back(msSince(t0));
    }
    p.wallMs = msSince(start);
    p.after = volumeCounts(session);
    return p;
}

nlohmann::json phaseJson(const Phase& p, int count) {
    return {{"frames", count},
            {"ms_per_frame", p.wallMs / std::max(count, 1)},
            {"fps", 1e3 * std::max(count, 1) / std::max(p.wallMs, 1e-9)},
            {"volume_uploads", p.after.uploads - p.before.uploads},
            {"volume_frames_reshown", p.after.reshown - p.before.reshown}};
}

} // namespace

int viewerPlayBench(const ViewerPlayOptions& o) {
    gpu::HeadlessContext context;
    session::ViewSession session(context.info(), o.scene, o.overrides, "", o.width, o.height);
    session::TimelinePlayer player(session);
    VEIL_CHECK(player.animated(), "--viewer-play: scene '{}' has no frame range to play{}", o.scene,
               player.status().empty() ? "" : " (" + player.status() + ")");
    VEIL_CHECK(o.frames > 0 && o.warmup >= 0 && o.scrubBack >= 0,
               "--viewer-play: --frames must be > 0, --warmup and --scrub-back >= 0");
    VEIL_CHECK(session.renderFrame(false), "--viewer-play: the first frame failed: {}",
               session.lastError());
    player.setLoop(true);
    player.play(true);
    play(session, player, o.warmup, false, o.timeoutS);
    const Phase forward = play(session, player, o.frames, false, o.timeoutS);
    player.play(false);
    const scene::FrameRange& range = player.range();
    const int span = (range.last - range.first) / std::max(range.step, 1) + 1;
    const int back = std::min(o.scrubBack, span - 1);
    Phase scrub;
    if (back > 0) scrub = play(session, player, back, true, o.timeoutS);

    nlohmann::json out;
    out["mode"] = "viewer timeline playback without a window (TimelinePlayer::update + "
                  "ViewSession::renderFrame + glFinish per frame, every frame of the range "
                  "shown in turn as soon as it is ready)";
    out["scene"] = o.scene;
    out["width"] = o.width;
    out["height"] = o.height;
    out["warmup"] = o.warmup;
    out["range"] = {range.first, range.last, range.step};
    out["renderer"] = context.info().renderer;
    out["oit"] = session.renderer().oitName();
    out["frames_replaced"] = session.framesReplaced();
    out["play"] = phaseJson(forward, o.frames);
    nlohmann::json passes = nlohmann::json::array({passStats("wait", forward.wait),
                                                   passStats("show", forward.show),
                                                   passStats("render", forward.render),
                                                   passStats("frame", forward.frame),
                                                   {{"name", "play_frame"},
                                                    {"median_ms", forward.wallMs / o.frames},
                                                    {"min_ms", forward.wallMs / o.frames},
                                                    {"max_ms", forward.wallMs / o.frames}}});
    if (back > 0) {
        out["scrub_back"] = phaseJson(scrub, back);
        passes.push_back(passStats("scrub_show", scrub.show));
        passes.push_back(passStats("scrub_frame", scrub.frame));
    }
    out["passes"] = passes;
    out["times"] = "per shown frame: wait = UI frames that found the frame not ready yet, show "
                   "= TimelinePlayer::update showing it (volumes replaced: uploaded, or taken "
                   "from the frames held on the GPU), render = renderFrame + glFinish, frame = "
                   "all of it; play_frame = the loop's wall clock / frames (the metric)";
    const std::string text = out.dump(2);
    if (!o.json.empty()) writeTextFileAtomically(o.json, text + "\n");
    std::cout << text << "\n";
    return 0;
}

} // namespace veil::bench
