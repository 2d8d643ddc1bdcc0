// The viewer's timeline (play, pause, step, scrub, loop, fps) over an animated scene's frames:
// file sequences, camera keys and turntables, light keys (scene/timeline.h). Frames are
// streamed by a FrameCache (frame_cache.h) on a background thread; update() shows the frame
// aimed at once it is ready (ViewSession::showFrame: a frame of the same structure replaces
// only the volumes' data, camera and lights in the renderer; another builds the renderer
// with the frame's grids and GPU conversions preloaded), so the UI thread only uploads. Until then
// the last frame stays shown and status() says so; a frame that cannot be loaded (a missing or
// corrupt file) is recorded as the session's error, the last frame stays and the timeline keeps
// going.
#pragma once

#include "scene/timeline.h"
#include "viewer/session/frame_cache.h"
#include "viewer/session/view_session.h"

#include <cstdint>
#include <memory>
#include <string>

namespace veil::session {

class TimelinePlayer {
public:
    // The timeline of the session's scene: its frames (scene::sceneFrameRange), the frame the
    // session shows (time.frame, else the first), time.fps; the cache holds at most
    // time.prefetch_budget_mib. A scene that cannot be read as an animated scene (a bare .vdb)
    // has one frame.
    explicit TimelinePlayer(const ViewSession& session);
    ~TimelinePlayer();

    bool animated() const { return range_.first != range_.last; }
    const scene::FrameRange& range() const { return range_; }
    int target() const { return target_; } // the frame aimed at
    int shown() const { return shown_; }   // the frame the session shows
    bool playing() const { return playing_; }
    bool looping() const { return loop_; }
    double fps() const { return fps_; }
    // The target is neither shown nor failed (a script waits for it).
    bool pending() const { return target_ != shown_ && target_ != failed_; }
    const std::string& status() const { return status_; }
    const FrameCache* cache() const { return cache_.get(); }

    void play(bool on) { playing_ = on && animated(); }
    void seek(int frame);  // clamped to the range (a scrub, a "frame" action)
    void step(int frames); // by steps of the range, wrapping when looping
    void setLoop(bool on) { loop_ = on; }
    void setFps(double fps);

    // Once per UI frame, before the frame renders: advances a playing timeline (by wall clock,
    // `dtSeconds` x fps frames; `scripted`: one frame per call once the last one was shown, so
    // scripts are deterministic), asks the cache for the target and the frames after it, and
    // shows the target when it is ready. Never waits for a load.
    void update(ViewSession& session, double dtSeconds, bool scripted);

private:
    int advance(int from, int frames, bool& stopped) const;

    std::shared_ptr<scene::AnimatedScene> scene_;
    std::unique_ptr<FrameCache> cache_;
    scene::FrameRange range_;
    int target_ = 1, shown_ = 1, failed_ = INT32_MIN;
    bool playing_ = false, loop_ = true;
    double fps_ = 24.0, clock_ = 0.0;
    std::string status_;
};

} // namespace veil::session
