// Frames of an animated scene streamed from disk for the viewer's timeline: one background
// thread prepares the frames asked for (sequence/prefetch.h prepareFrame: the scene at the
// frame, its grids read and converted for the GPU) in the order asked, into a cache of
// prepared frames that drops the least recently used ones beyond a byte budget. Asking and
// looking up never wait for a load.
#pragma once

#include "scene/timeline.h"
#include "sequence/prefetch.h"

#include <condition_variable>
#include <cstddef>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace veil::session {

class FrameCache {
public:
    // `scene` stays alive with the cache; `max3D`: GL_MAX_3D_TEXTURE_SIZE for the conversions.
    // Throws veil::Error when a file volume that is not a sequence cannot be read.
    FrameCache(std::shared_ptr<const scene::AnimatedScene> scene, std::size_t budgetBytes,
               int max3D);
    ~FrameCache(); // stops the thread (a load in progress finishes first)
    FrameCache(const FrameCache&) = delete;
    FrameCache& operator=(const FrameCache&) = delete;

    // The frames wanted, most urgent first; replaces the previous list. The first is loaded
    // whatever the budget; the others while the cache holds less than the budget (so it
    // exceeds the budget by one frame at most). Frames no longer wanted are dropped, least
    // recently used first, while the cache holds more than the budget.
    void want(std::vector<int> frames);
    // The prepared frame (made most recently used), or null while it is not ready. A frame
    // that could not be prepared is returned with its error set.
    std::shared_ptr<const sequence::PreparedFrame> find(int frame);

    std::size_t bytes() const;  // held by the cached frames' grids and conversions
    std::size_t frames() const; // frames cached
    std::size_t loads() const;  // frames prepared since the start (evicted ones count again)

private:
    void work();
    void evict(); // frames not wanted, least recently used first, down to the budget

    std::shared_ptr<const scene::AnimatedScene> scene_;
    std::vector<volume::PreloadedGrid> staticGrids_;
    sequence::StaticConversions conversions_; // of staticGrids_, made once
    std::size_t budget_;
    int max3D_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<int> wanted_;
    std::list<int> recent_; // front: most recently used
    struct Entry {
        std::shared_ptr<const sequence::PreparedFrame> frame;
        std::list<int>::iterator age;
    };
    std::map<int, Entry> cache_;
    std::size_t bytes_ = 0, loads_ = 0;
    bool stop_ = false;
    std::thread thread_;
};

} // namespace veil::session
