// The viewer's timeline (timeline_player.h).
#include "viewer/session/timeline_player.h"

#include "base/error.h"
#include "base/text.h"
#include "grid/grid_preload.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace veil::session {

namespace {

// The session's overrides without time.frame (the player sets it).
std::vector<std::string> withoutFrame(const std::vector<std::string>& overrides, int* frame) {
    std::vector<std::string> out;
    for (const std::string& o : overrides) {
        if (o.rfind("time.frame=", 0) == 0) {
            try {
                *frame = std::stoi(o.substr(11));
            } catch (const std::exception&) {
            }
            continue;
        }
        out.push_back(o);
    }
    return out;
}

} // namespace

TimelinePlayer::TimelinePlayer(const ViewSession& session) {
    range_ = {1, 1, 1};
    if (lowerExtension(session.scenePath().string()) != ".json") return;
    int frame = INT32_MIN;
    const std::vector<std::string> overrides = withoutFrame(session.overrides(), &frame);
    try {
        scene_ = std::make_shared<scene::AnimatedScene>(
            scene::loadAnimatedScene(session.scenePath(), overrides));
    } catch (const Error& e) {
        status_ = e.what();
        return;
    }
    range_ = scene::sceneFrameRange(scene_->timeline);
    fps_ = scene_->timeline.time.fps > 0 ? scene_->timeline.time.fps : 24.0;
    shown_ = target_ = frame != INT32_MIN ? frame : scene::defaultFrame(scene_->timeline);
    if (!animated()) return;
    try {
        cache_ = std::make_unique<FrameCache>(
            scene_, std::size_t(scene_->timeline.time.prefetchBudgetMiB) << 20,
            session.context().max3DTextureSize);
    } catch (const Error& e) {
        status_ = e.what();
        range_ = {shown_, shown_, 1};
    }
}

TimelinePlayer::~TimelinePlayer() = default;

void TimelinePlayer::seek(int frame) {
    target_ = std::clamp(frame, range_.first, range_.last);
    clock_ = 0.0;
}

void TimelinePlayer::setFps(double fps) { fps_ = std::clamp(fps, 0.1, 1000.0); }

int TimelinePlayer::advance(int from, int frames, bool& stopped) const {
    stopped = false;
    const int n = (range_.last - range_.first) / range_.step + 1;
    int i = (from - range_.first) / range_.step + frames;
    if (i >= n || i < 0) {
        if (loop_) {
            i = ((i % n) + n) % n;
        } else {
            stopped = true;
            i = std::clamp(i, 0, n - 1);
        }
    }
    return range_.first + i * range_.step;
}

void TimelinePlayer::step(int frames) {
    bool stopped = false;
    target_ = advance(target_, frames, stopped);
}

void TimelinePlayer::update(ViewSession& session, double dtSeconds, bool scripted) {
    if (!cache_) return;
    if (playing_) {
        int frames = 0;
        if (scripted) {
            frames = pending() ? 0 : 1;
        } else {
            clock_ += dtSeconds * fps_;
            frames = static_cast<int>(std::floor(clock_));
            clock_ -= frames;
        }
        if (frames > 0) {
            bool stopped = false;
            target_ = advance(target_, frames * 1, stopped);
            if (stopped) playing_ = false;
        }
    }
    // The target first, then the frames after it in playing order.
    std::vector<int> wanted{target_};
    bool stopped = false;
    for (int k = 1; k <= 4 && animated(); ++k) {
        const int f = advance(target_, k, stopped);
        if (stopped || f == target_) break;
        wanted.push_back(f);
    }
    cache_->want(wanted);
    if (target_ != shown_ && target_ != failed_) {
        const auto p = cache_->find(target_);
        if (!p) {
            status_ = fmt::format("frame {} loading; showing frame {}", target_, shown_);
        } else if (!p->error.empty()) {
            failed_ = target_;
            session.fail(p->error);
            status_ =
                fmt::format("frame {} failed ({}); showing frame {}", target_, p->error, shown_);
        } else {
            if (session.showFrame(target_, p->grids)) {
                shown_ = target_;
                failed_ = INT32_MIN;
                status_ = fmt::format("frame {}", shown_);
            } else {
                failed_ = target_;
                status_ = fmt::format("frame {} failed ({}); showing frame {}", target_,
                                      session.lastError(), shown_);
            }
        }
    }
}

} // namespace veil::session
