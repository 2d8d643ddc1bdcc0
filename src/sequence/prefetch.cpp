// Frame-ordered read-ahead of a frame range's grids (prefetch.h).
#include "sequence/prefetch.h"

#include "base/error.h"
#include "scene/timeline.h"
#include "volume/density_grid.h"

#include <algorithm>
#include <chrono>

namespace veil::sequence {

FramePrefetcher::FramePrefetcher(const scene::AnimatedScene& scene, std::vector<int> frames,
                                 std::size_t budgetBytes, int threads)
    : scene_(scene), frames_(std::move(frames)), budget_(budgetBytes) {
    slots_.resize(frames_.size());
    // File volumes that do not change with the frame are read once, here (errors surface at
    // once); procedural ones are built by each frame's renderer.
    for (std::size_t i = 0; i < scene.scene.volumes.size(); ++i) {
        const scene::VolumeRef& v = scene.scene.volumes[i];
        const bool sequence = i < scene.timeline.volumes.size() && scene.timeline.volumes[i];
        if (!sequence && v.procedural.empty())
            staticGrids_.push_back({v.path, v.grid, volume::loadVolume(v)});
    }
    const int n = std::clamp(threads, 1, 64);
    for (int i = 0; i < n; ++i)
        workers_.emplace_back([this] { work(); });
}

FramePrefetcher::~FramePrefetcher() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    space_.notify_all();
    for (std::thread& t : workers_)
        t.join();
}

std::size_t FramePrefetcher::peakBytes() const {
    std::lock_guard lock(mutex_);
    return peakBytes_;
}

PreparedFrame FramePrefetcher::prepare(int frame) const {
    const auto start = std::chrono::steady_clock::now();
    PreparedFrame p;
    p.frame = frame;
    try {
        p.scene = scene::sceneAtFrame(scene_, frame, &p.notes);
        p.grids = staticGrids_;
        for (const scene::VolumeRef& v : p.scene.volumes) {
            if (!v.procedural.empty()) continue;
            if (volume::findPreloadedGridIn(p.grids, v.path, v.grid)) continue;
            p.grids.push_back({v.path, v.grid, volume::loadVolume(v)});
        }
        for (const volume::PreloadedGrid& g : p.grids) {
            p.bytes += g.value->memUsage();
            p.activeVoxels += g.value->activeVoxelCount();
        }
    } catch (const Error& e) {
        p.error = e.what();
        p.grids.clear();
    } catch (const std::exception& e) {
        p.error = fmt::format("frame {}: {}", frame, e.what());
        p.grids.clear();
    }
    p.readMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return p;
}

void FramePrefetcher::work() {
    for (;;) {
        std::size_t index = 0;
        {
            std::unique_lock lock(mutex_);
            // The frame right after the one taken last may always start; later ones wait for
            // room in the budget.
            space_.wait(lock, [&] {
                return stop_ || claimed_ >= frames_.size() || claimed_ <= next_ ||
                       heldBytes_ < budget_;
            });
            if (stop_ || claimed_ >= frames_.size()) return;
            index = claimed_++;
        }
        auto p = std::make_unique<PreparedFrame>(prepare(frames_[index]));
        {
            std::lock_guard lock(mutex_);
            heldBytes_ += p->bytes;
            peakBytes_ = std::max(peakBytes_, heldBytes_);
            slots_[index] = std::move(p);
        }
        ready_.notify_all();
    }
}

PreparedFrame FramePrefetcher::take() {
    std::unique_lock lock(mutex_);
    VEIL_CHECK(next_ < frames_.size(), "no frame left to take");
    ready_.wait(lock, [&] { return slots_[next_] != nullptr; });
    PreparedFrame p = std::move(*slots_[next_]);
    slots_[next_].reset();
    heldBytes_ -= p.bytes;
    ++next_;
    lock.unlock();
    space_.notify_all();
    return p;
}

} // namespace veil::sequence
