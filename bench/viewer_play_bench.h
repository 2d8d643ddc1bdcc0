// veil-bench --viewer-play: the viewer's timeline played without a window (viewer/session/
// timeline_player.h over a ViewSession, as `veil view` plays it): every frame of the range is
// streamed by the timeline's frame cache, shown (ViewSession::showFrame: the volumes' data,
// camera and lights replaced in the renderer, or the frame taken from those held on the GPU)
// and rendered, as fast as they come; then, with --scrub-back N, N frames stepped backwards
// over the frames just played, as a scrub of the slider does (bench/README.md,
// bench/sets/sequence-playback.json).
#pragma once

#include <string>
#include <vector>

namespace veil::bench {

struct ViewerPlayOptions {
    std::string scene, json;
    std::vector<std::string> overrides;
    int width = 1920, height = 1080;
    int frames = 60;         // frames shown after the warm-up, looping over the scene's range
    int warmup = 4;          // frames shown first, not timed
    int scrubBack = 0;       // then this many frames stepped backwards
    double timeoutS = 300.0; // a frame that never comes (a broken file) ends the run
};

int viewerPlayBench(const ViewerPlayOptions& o);

} // namespace veil::bench
