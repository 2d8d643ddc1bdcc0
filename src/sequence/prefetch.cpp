// Frame-ordered read-ahead of a frame range's grids (prefetch.h).
#include "sequence/prefetch.h"

#include "base/error.h"
#include "fog/fog_pass.h"
#include "frame/renderer.h"
#include "grid/density_grid.h"
#include "grid/vdb_file.h"
#include "scene/timeline.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <utility>

namespace veil::sequence {

namespace {

// The fog pass's options for each grid volume in scene order (fog/fog_pass.cpp: the budget
// left by the volumes before it). A procedural volume before a file one leaves the rest to the
// renderer (its size is known only once built); so does a conversion that fails, whose error
// the renderer then gives with the volume's place in the scene.
// `grid` converted, with `channel` (a temperature grid) as its emission channel when given,
// to be held on the GPU under `key` within `holdBytes` (GridConversion::gpuKey).
std::shared_ptr<const volume::GridConversion> convert(const openvdb::FloatGrid& grid,
                                                      const openvdb::FloatGrid::Ptr& channel,
                                                      const volume::GpuVolumeOptions& options,
                                                      int max3D, const std::string& key,
                                                      std::size_t holdBytes) {
    auto c = std::make_shared<volume::GridConversion>(volume::convertGrid(grid, options, max3D));
    if (channel) volume::addChannel(*c, {channel});
    volume::packHalf(*c); // here on the worker: the render thread's upload only copies them
    c->gpuKey = key;
    c->gpuHoldBytes = holdBytes;
    return c;
}

// What the conversion of `v`'s grid with `options` for `max3D` is made of, the key its frame
// is held under on the GPU (fog/gpu_volume.h): the file (with its size and modification time:
// a file written again is new data), the grid, its temperature channel, the options.
std::string gpuKey(const scene::VolumeRef& v, const volume::GpuVolumeOptions& o, int max3D) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(v.path, ec);
    const auto time = std::filesystem::last_write_time(v.path, ec).time_since_epoch().count();
    return fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}",
                       std::filesystem::absolute(v.path, ec).string(), v.grid, v.temperatureGrid,
                       size, time, o.budgetBytes, o.refuseOverBudget, o.denseVoxelLimit,
                       o.neighbourhood, max3D);
}

bool sameOptions(const volume::GpuVolumeOptions& a, const volume::GpuVolumeOptions& b) {
    return a.budgetBytes == b.budgetBytes && a.refuseOverBudget == b.refuseOverBudget &&
           a.denseVoxelLimit == b.denseVoxelLimit && a.neighbourhood == b.neighbourhood;
}

void convertAhead(PreparedFrame& p, int max3D, const std::vector<volume::PreloadedGrid>& statics,
                  StaticConversions* conversions) {
    std::size_t used = 0;
    // The frames held on the GPU: render.sequence_gpu_cache_mib shared by the grid volumes.
    const std::size_t grids = std::size_t(
        std::count_if(p.scene.volumes.begin(), p.scene.volumes.end(),
                      [](const scene::VolumeRef& v) { return v.procedural != "homogeneous"; }));
    const std::size_t holdBytes =
        (std::size_t(p.scene.render.sequenceGpuCacheMiB) << 20) / std::max<std::size_t>(grids, 1);
    for (const scene::VolumeRef& v : p.scene.volumes) {
        if (v.procedural == "homogeneous") continue;
        if (!v.procedural.empty()) return;
        auto g = std::find_if(p.grids.begin(), p.grids.end(),
                              [&](const auto& x) { return x.path == v.path && x.grid == v.grid; });
        if (g == p.grids.end()) return;
        volume::GpuVolumeOptions options;
        options.budgetBytes = std::size_t(p.scene.render.volumeBudgetMiB) << 20;
        options.budgetBytes = options.budgetBytes > used ? options.budgetBytes - used : 0;
        options.refuseOverBudget = p.scene.render.volumeOverBudget == "refuse";
        options.neighbourhood =
            p.scene.render.fogOctaveRadius > 0.0f && p.scene.render.fogOctaves > 1;
        if (g->converted) return; // one grid under two budgets: the renderer converts the rest
        // A colour or scalar emission grid: the fog pass converts the volume itself.
        if (!v.emissionGrid.empty()) return;
        if (!v.temperatureGrid.empty()) {
            // Density and temperature in one layout, as the fog pass makes it: the density
            // planned within half the budget left, the channel sampled at its texels.
            if (!volume::findPreloadedGridIn(p.grids, v.path, v.temperatureGrid)) return;
            options.budgetBytes /= 2;
        }
        const openvdb::FloatGrid::Ptr channel =
            v.temperatureGrid.empty()
                ? nullptr
                : volume::findPreloadedGridIn(p.grids, v.path, v.temperatureGrid);
        const bool isStatic =
            conversions && std::any_of(statics.begin(), statics.end(),
                                       [&](const auto& s) { return s.value == g->value; });
        try {
            const std::string key = gpuKey(v, options, max3D);
            g->converted =
                isStatic ? conversions->get(*g->value, channel, options, max3D, key, holdBytes)
                         : convert(*g->value, channel, options, max3D, key, holdBytes);
        } catch (const Error&) {
            return;
        }
        g->channel = v.temperatureGrid;
        g->options = options;
        g->max3D = max3D;
        used += g->converted->stats.gpuBytes;
        if (!isStatic) p.bytes += g->converted->bytes(); // static ones are held once
    }
}

// Whether a renderer built on `current` can take the frame `next` by replacing its volumes'
// data (Renderer::replaceVolumes): the same volumes (names, grids, emission; file volumes
// only), lights and cameras. A scattered-light cache follows (FogPass::replaceVolume): baked
// again when a volume's file, a light or the ambient changed, kept when only the camera moved.
bool sameStructure(const scene::Scene& current, const scene::Scene& next) {
    if (current.volumes.size() != next.volumes.size() ||
        current.lights.size() != next.lights.size() ||
        current.cameras.size() != next.cameras.size())
        return false;
    for (std::size_t i = 0; i < next.volumes.size(); ++i) {
        const scene::VolumeRef& a = current.volumes[i];
        const scene::VolumeRef& b = next.volumes[i];
        if (a.name != b.name || a.procedural != b.procedural || a.grid != b.grid ||
            a.temperatureGrid != b.temperatureGrid || a.emissionGrid != b.emissionGrid)
            return false;
        if (!b.procedural.empty() && b.procedural != "homogeneous") return false;
    }
    return true;
}

// The conversion of every grid volume of the prepared frame, made ahead for `max3D` (with its
// temperature channel where the volume has one), in scene order; false when one is missing.
bool conversionsOf(const scene::Scene& scene, const std::vector<volume::PreloadedGrid>& grids,
                   int max3D, std::vector<const volume::GridConversion*>& out) {
    out.clear();
    for (const scene::VolumeRef& v : scene.volumes) {
        if (v.procedural == "homogeneous") continue;
        const auto g = std::find_if(grids.begin(), grids.end(), [&](const auto& x) {
            return x.path == v.path && x.grid == v.grid && x.converted && x.max3D == max3D &&
                   x.channel == v.temperatureGrid;
        });
        if (g == grids.end() || !v.emissionGrid.empty()) return false;
        out.push_back(g->converted.get());
    }
    return !out.empty();
}

// The next frame's values into the scene the renderer references, element by element (the
// fog pass keeps pointers to the volume entries).
void advanceScene(scene::Scene& current, const scene::Scene& next) {
    for (std::size_t i = 0; i < next.volumes.size(); ++i)
        current.volumes[i] = next.volumes[i];
    for (std::size_t i = 0; i < next.lights.size(); ++i)
        current.lights[i] = next.lights[i];
    for (std::size_t i = 0; i < next.cameras.size(); ++i)
        current.cameras[i] = next.cameras[i];
}

// The uploads from host memory of `r`'s grid volumes so far and their bytes as sent
// (GpuVolumeStats: a frame held on the GPU and shown again uploads nothing).
std::pair<std::size_t, std::size_t> volumeUploads(const frame::Renderer& r) {
    std::pair<std::size_t, std::size_t> n{0, 0};
    if (const volume::FogPass* fog = r.fog())
        for (const volume::GpuVolumeStats& s : fog->stats()) {
            n.first += s.uploads;
            n.second += s.uploadedBytes;
        }
    return n;
}

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

} // namespace

FramePrefetcher::FramePrefetcher(const scene::AnimatedScene& scene, std::vector<int> frames,
                                 std::size_t budgetBytes, int threads, int max3D)
    : scene_(scene), frames_(std::move(frames)), budget_(budgetBytes), max3D_(max3D) {
    slots_.resize(frames_.size());
    staticGrids_ = readStaticGrids(scene);
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

bool replaceableBy(const scene::Scene& current, const scene::Scene& next,
                   const std::vector<volume::PreloadedGrid>& grids, int max3D,
                   std::vector<const volume::GridConversion*>& out) {
    return sameStructure(current, next) && conversionsOf(next, grids, max3D, out);
}

std::vector<volume::PreloadedGrid> readStaticGrids(const scene::AnimatedScene& scene) {
    // Procedural volumes are built by each frame's renderer.
    std::vector<volume::PreloadedGrid> grids;
    for (std::size_t i = 0; i < scene.scene.volumes.size(); ++i) {
        const scene::VolumeRef& v = scene.scene.volumes[i];
        const bool sequence = i < scene.timeline.volumes.size() && scene.timeline.volumes[i];
        if (!sequence && v.procedural.empty()) {
            const volume::VdbReadScope oneRead;
            grids.push_back({v.path, v.grid, volume::loadVolume(v), nullptr, {}, 0, {}});
            const std::string& channel =
                v.temperatureGrid.empty() ? v.emissionGrid : v.temperatureGrid;
            if (channel.empty()) continue;
            const std::vector<openvdb::FloatGrid::Ptr> c = volume::loadEmissionChannel(v);
            if (c.size() == 1) grids.push_back({v.path, channel, c[0], nullptr, {}, 0, {}});
        }
    }
    return grids;
}

std::shared_ptr<const volume::GridConversion>
StaticConversions::get(const openvdb::FloatGrid& grid, const openvdb::FloatGrid::Ptr& channel,
                       const volume::GpuVolumeOptions& options, int max3D, const std::string& key,
                       std::size_t holdBytes) {
    const std::lock_guard lock(mutex_); // the first frames' workers wait for one conversion
    for (const Item& i : items_)
        if (i.grid == &grid && i.channel == channel.get() && i.max3D == max3D &&
            sameOptions(i.options, options))
            return i.converted;
    auto c = convert(grid, channel, options, max3D, key, holdBytes);
    items_.push_back({&grid, channel.get(), options, max3D, c});
    return c;
}

std::size_t StaticConversions::conversions() const {
    const std::lock_guard lock(mutex_);
    return items_.size();
}

PreparedFrame prepareFrame(const scene::AnimatedScene& scene, int frame,
                           const std::vector<volume::PreloadedGrid>& staticGrids, int max3D,
                           StaticConversions* conversions) {
    const auto start = std::chrono::steady_clock::now();
    PreparedFrame p;
    p.frame = frame;
    try {
        p.scene = scene::sceneAtFrame(scene, frame, &p.notes);
        p.grids = staticGrids;
        // A file is read once for all the grids the frame takes from it.
        const volume::VdbReadScope oneReadPerFile;
        for (const scene::VolumeRef& v : p.scene.volumes) {
            if (!v.procedural.empty()) continue;
            if (!volume::findPreloadedGridIn(p.grids, v.path, v.grid))
                p.grids.push_back({v.path, v.grid, volume::loadVolume(v), nullptr, {}, 0, {}});
            // The emission channel's grid too (a colour emission grid is left to the fog pass).
            const std::string& channel =
                v.temperatureGrid.empty() ? v.emissionGrid : v.temperatureGrid;
            if (channel.empty() || volume::findPreloadedGridIn(p.grids, v.path, channel)) continue;
            const std::vector<openvdb::FloatGrid::Ptr> c = volume::loadEmissionChannel(v);
            if (c.size() == 1) p.grids.push_back({v.path, channel, c[0], nullptr, {}, 0, {}});
        }
        for (const volume::PreloadedGrid& g : p.grids) {
            p.bytes += g.value->memUsage();
            const bool density =
                std::any_of(p.scene.volumes.begin(), p.scene.volumes.end(),
                            [&](const auto& v) { return v.path == g.path && v.grid == g.grid; });
            if (density) p.activeVoxels += g.value->activeVoxelCount();
        }
        p.readMs = msSince(start);
        if (max3D > 0) {
            const auto converting = std::chrono::steady_clock::now();
            convertAhead(p, max3D, staticGrids, conversions);
            p.convertMs = msSince(converting);
        }
    } catch (const Error& e) {
        p.error = e.what();
        p.grids.clear();
    } catch (const std::exception& e) {
        p.error = fmt::format("frame {}: {}", frame, e.what());
        p.grids.clear();
    }
    if (!p.error.empty()) p.readMs = msSince(start);
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
        auto p = std::make_unique<PreparedFrame>(
            prepareFrame(scene_, frames_[index], staticGrids_, max3D_, &conversions_));
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

GridReleaser::GridReleaser() {
    thread_ = std::thread([this] {
        std::unique_lock lock(mutex_);
        for (;;) {
            wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (queue_.empty()) return; // stopped, everything freed
            std::vector<volume::PreloadedGrid> grids = std::move(queue_.front());
            queue_.pop_front();
            lock.unlock();
            grids.clear();
            lock.lock();
        }
    });
}

GridReleaser::~GridReleaser() {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void GridReleaser::release(std::vector<volume::PreloadedGrid>&& grids) {
    if (grids.empty()) return;
    {
        const std::lock_guard lock(mutex_);
        queue_.push_back(std::move(grids));
    }
    grids.clear();
    wake_.notify_one();
}

RangeRenderer::RangeRenderer(const gpu::ContextInfo& context, frame::RendererOptions options,
                             int max3D)
    : context_(context), options_(std::move(options)), max3D_(max3D) {}

RangeRenderer::~RangeRenderer() = default;

bool RangeRenderer::upload(PreparedFrame& p) {
    if (p.uploaded) return true;
    if (!renderer_ || !replaceableBy(current_, p.scene, p.grids, max3D_, conversions_))
        return false;
    const auto start = std::chrono::steady_clock::now();
    // The volume entries first: the upload places the data with the new frame's transforms.
    // The camera and lights follow in next(), after the current frame's image is read back.
    for (std::size_t i = 0; i < p.scene.volumes.size(); ++i)
        current_.volumes[i] = p.scene.volumes[i];
    const volume::PreloadedGridScope preloaded(p.grids); // a scattered-light cache's grids
    const auto before = volumeUploads(*renderer_);
    renderer_->uploadVolumes(conversions_);
    const auto after = volumeUploads(*renderer_);
    uploads_ += after.first - before.first;
    uploadedBytes_ += after.second - before.second;
    lastUploadMs_ = msSince(start);
    p.uploaded = true;
    releaser_.release(std::move(p.grids)); // copied into the staging buffer
    return true;
}

frame::Renderer& RangeRenderer::next(PreparedFrame& p) {
    if (p.uploaded || upload(p)) {
        advanceScene(current_, p.scene);
        renderer_->showUploaded(options_.camera);
        ++reused_;
    } else {
        const auto start = std::chrono::steady_clock::now();
        renderer_.reset();
        current_ = std::move(p.scene);
        // The frame's grids come from the read-ahead (grid/grid_preload.h).
        const volume::PreloadedGridScope preloaded(p.grids);
        renderer_ = std::make_unique<frame::Renderer>(current_, context_, options_);
        ++built_;
        if (const volume::FogPass* fog = renderer_->fog())
            for (const volume::GpuVolumeStats& s : fog->stats()) {
                uploadedBytes_ += s.gpuBytes;
                ++uploads_;
            }
        lastUploadMs_ = msSince(start);
    }
    releaser_.release(std::move(p.grids)); // uploaded
    return *renderer_;
}

} // namespace veil::sequence
