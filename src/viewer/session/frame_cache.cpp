// The viewer's streamed frames (frame_cache.h).
#include "viewer/session/frame_cache.h"

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
    // Frames no longer wanted, least recently used first. Wanted frames stay: the look-ahead
    // stops once the budget is reached, so they exceed it by one frame at most.
    for (auto r = recent_.rbegin(); bytes_ > budget_ && r != recent_.rend();) {
        if (std::find(wanted_.begin(), wanted_.end(), *r) != wanted_.end()) {
            ++r;
            continue;
        }
        const auto it = cache_.find(*r);
        bytes_ -= it->second.frame->bytes;
        cache_.erase(it);
        r = std::make_reverse_iterator(recent_.erase(std::next(r).base()));
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
            sequence::prepareFrame(*scene_, frame, staticGrids_, max3D_, &conversions_));
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
