// The viewer's streamed frames (frame_cache.h).
#include "session/frame_cache.h"

#include <algorithm>

namespace veil::session {

FrameCache::FrameCache(std::shared_ptr<const scene::AnimatedScene> scene, std::size_t budgetBytes,
                       int max3D)
    : scene_(std::move(scene)), staticGrids_(sequence::readStaticGrids(*scene_)),
      budget_(budgetBytes), max3D_(max3D), thread_([this] { work(); }) {}

FrameCache::~FrameCache() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void FrameCache::want(std::vector<int> frames) {
    {
        std::lock_guard lock(mutex_);
        if (frames == wanted_) return;
        wanted_ = std::move(frames);
    }
    wake_.notify_all();
}

std::shared_ptr<const sequence::PreparedFrame> FrameCache::find(int frame) {
    std::lock_guard lock(mutex_);
    const auto it = cache_.find(frame);
    if (it == cache_.end()) return nullptr;
    recent_.splice(recent_.begin(), recent_, it->second.age);
    return it->second.frame;
}

std::size_t FrameCache::bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
}

std::size_t FrameCache::frames() const {
    std::lock_guard lock(mutex_);
    return cache_.size();
}

std::size_t FrameCache::loads() const {
    std::lock_guard lock(mutex_);
    return loads_;
}

void FrameCache::evict() {
    if (cache_.empty()) return;
    const int urgent = wanted_.empty() ? recent_.front() : wanted_.front();
    // Frames not wanted go first, oldest first; then wanted ones from the back of the list.
    auto wantedRank = [&](int f) {
        const auto w = std::find(wanted_.begin(), wanted_.end(), f);
        return w == wanted_.end() ? -1 : int(w - wanted_.begin());
    };
    while (bytes_ > budget_ && cache_.size() > 1) {
        int victim = urgent;
        int worst = -2;
        for (auto r = recent_.rbegin(); r != recent_.rend(); ++r) {
            if (*r == urgent) continue;
            const int rank = wantedRank(*r);
            const int score = rank < 0 ? 1 << 30 : rank; // not wanted: evict first
            if (score > worst) {
                worst = score;
                victim = *r;
            }
        }
        if (victim == urgent) return;
        const auto it = cache_.find(victim);
        bytes_ -= it->second.frame->bytes;
        recent_.erase(it->second.age);
        cache_.erase(it);
    }
}

void FrameCache::work() {
    std::unique_lock lock(mutex_);
    for (;;) {
        int frame = 0;
        bool found = false;
        wake_.wait(lock, [&] {
            if (stop_) return true;
            evict(); // the wish list changed: frames no longer wanted make room
            for (std::size_t i = 0; i < wanted_.size(); ++i) {
                if (cache_.count(wanted_[i])) continue;
                if (i > 0 && bytes_ >= budget_) return false; // look-ahead waits for room
                frame = wanted_[i];
                found = true;
                return true;
            }
            return false;
        });
        if (stop_) return;
        if (!found) continue;
        lock.unlock();
        auto p = std::make_shared<const sequence::PreparedFrame>(
            sequence::prepareFrame(*scene_, frame, staticGrids_, max3D_));
        lock.lock();
        ++loads_;
        if (cache_.count(frame)) continue;
        recent_.push_front(frame);
        bytes_ += p->bytes;
        cache_[frame] = Entry{std::move(p), recent_.begin()};
        evict();
    }
}

} // namespace veil::session
