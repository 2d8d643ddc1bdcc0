#include "fog/scattered_light_cache.h"

#include "base/error.h"
#include "base/log.h"
#include "base/progress.h"
#include "fog/gpu_volume.h"
#include "fog/scattered_light_bake.h"
#include "integrators/majorant_grid.h"
#include "integrators/medium.h"
#include "integrators/path_tracer.h"

#include "shaders/common/bindings.h"

#include <openvdb/tools/Count.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

namespace veil::volume {

namespace {

// Mesa's software rasterizers (llvmpipe, softpipe, swrast).
bool softwareRenderer() {
    const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return r &&
           (std::strstr(r, "llvmpipe") || std::strstr(r, "softpipe") || std::strstr(r, "swrast"));
}

} // namespace

ScatteredLightCache::ScatteredLightCache(const scene::Scene& scene,
                                         std::vector<openvdb::FloatGrid::ConstPtr> grids,
                                         ScatteredLightGpu gpu)
    : scene_(scene), grids_(std::move(grids)), coarsened_(gpu.coarsened) {
    const std::string& device = scene_.render.fogScatteredLightBake;
    const bool gpuBake =
        gpu.programs && (device == "gpu" || (device == "auto" && !softwareRenderer()));
    if (gpuBake)
        bake_ = std::make_unique<ScatteredLightBake>(*gpu.programs, std::move(gpu.defines),
                                                     std::move(gpu.bindVolumes));
    layout();
}

void ScatteredLightCache::layout() {
    // The path tracer's medium (its bounds; it loads the emission channels, from the frame's
    // read-ahead where a PreloadedGridScope is alive).
    const Medium medium(scene_, grids_, "path tracer", false);
    medium.worldBounds(lo_, hi_);
    VEIL_CHECK(glm::all(glm::lessThan(lo_, hi_)),
               "scattered-light cache: the volumes have no bounds");
    dims_ = scatteredLightDims(scene_, grids_, lo_, hi_);
    if (!bake_) return;
    gridMax_.clear();
    for (const auto& g : grids_)
        gridMax_.push_back(double(openvdb::tools::minMax(g->tree()).max()));
    majorantDims_ = majorantDims(scene_, grids_, lo_, hi_);
    gridMajorants_.clear();
    std::size_t g = 0;
    for (const auto& v : scene_.volumes)
        if (v.procedural != "homogeneous" && g < grids_.size())
            gridMajorants_.push_back(gridMajorants(*grids_[g++], v.transform, lo_, hi_,
                                                   majorantDims_, coarseningMargin(coarsened_)));
}

void ScatteredLightCache::replaceGrid(std::size_t i, openvdb::FloatGrid::ConstPtr grid,
                                      int coarsened) {
    VEIL_CHECK(i < grids_.size() && grid, "scattered-light cache: no grid volume {} to replace", i);
    if (grids_[i] == grid && coarsened_ == coarsened) return; // the same data: no new bake
    grids_[i] = std::move(grid);
    coarsened_ = coarsened;
    layout(); // now, while the caller's read-ahead scope holds the frame's grids
    ++dataVersion_;
}

ScatteredLightCache::~ScatteredLightCache() = default;

std::vector<float> ScatteredLightCache::key() const {
    std::vector<float> k{scene_.render.ambient.x, scene_.render.ambient.y, scene_.render.ambient.z,
                         float(scene_.render.seed), float(dataVersion_)};
    for (const auto& l : scene_.lights) {
        k.insert(k.end(), {float(l.type), l.color.x, l.color.y, l.color.z, l.intensity,
                           l.direction.x, l.direction.y, l.direction.z, l.position.x, l.position.y,
                           l.position.z, l.innerConeDegrees, l.outerConeDegrees});
    }
    for (const auto& v : scene_.volumes)
        k.insert(k.end(), {v.densityScale, v.albedo.x, v.albedo.y, v.albedo.z, v.anisotropy,
                           v.emission.x, v.emission.y, v.emission.z});
    return k;
}

bool ScatteredLightCache::converging() const { return bake_ && started_ && !bake_->done(); }

void ScatteredLightCache::startGpuBake() {
    ScatteredLightBake::Setup setup;
    setup.lo = lo_;
    setup.hi = hi_;
    setup.dims = dims_;
    setup.samples = scene_.render.fogScatteredLightSamples;
    setup.seed = scene_.render.seed;
    // More paths where surfaces read the cache (the objects' bounds now: moving one later
    // does not bake again, the next bake follows it).
    ScatteredLightSurface surface = scatteredLightSurfaceTexels(scene_, lo_, hi_, dims_);
    setup.surfaceTexels = std::move(surface.texels);
    setup.surfaceSamples = surface.samples;
    // The grids' majorants times their density scales, summed over the volumes. A volume with
    // an emission grid emits where its density may be 0: there its cells keep a majorant of
    // 1/20 of its largest extinction, so that the null-collision estimator samples the emission.
    setup.majorantDims = majorantDims_;
    setup.majorants.assign(gridMajorants_.empty() ? 0 : gridMajorants_[0].size(), 0.0f);
    std::size_t g = 0;
    for (const auto& v : scene_.volumes) {
        if (v.procedural == "homogeneous" || g >= gridMajorants_.size()) continue;
        const float scale = std::max(0.0f, v.densityScale);
        const float floor = v.emissionGrid.empty() ? 0.0f : 0.05f * scale * float(gridMax_[g]);
        const std::vector<float>& m = gridMajorants_[g++];
        for (std::size_t i = 0; i < m.size(); ++i)
            if (m[i] >= 0.0f) setup.majorants[i] += std::max(scale * m[i], floor);
    }
    bake_->start(scene_, setup);
}

void ScatteredLightCache::bakeOnCpu() {
    const int samples = scene_.render.fogScatteredLightSamples;
    const std::size_t cells = std::size_t(dims_.x) * dims_.y * dims_.z;
    const ScatteredLightSurface surface = scatteredLightSurfaceTexels(scene_, lo_, hi_, dims_);
    ProgressNote note(fmt::format(
        "baking scattered-light cache on the CPU: {} cells x {} paths{}", cells, samples,
        surface.texels.empty()
            ? std::string()
            : fmt::format(" ({} near surfaces x {})", surface.texels.size(), surface.samples)));
    PathTracerSettings settings;
    settings.seed = scene_.render.seed;
    const VolumePathTracer tracer(scene_, grids_, settings);
    const ScatteredLight s = tracer.scatteredLight(
        lo_, hi_, dims_, samples, [&note](double done) { note.set(done); }, surface.texels,
        surface.samples);
    mean_ = makeFilteredTexture3D(dims_, GL_RGBA32F, GL_RGBA, &s.mean[0].x);
    flux_ = makeFilteredTexture3D(dims_, GL_RGBA32F, GL_RGBA, &s.flux[0].x);
}

void ScatteredLightCache::ensure() {
    std::vector<float> k = key();
    const bool stale = !started_ || k != bakedKey_;
    if (!stale && !converging()) return;
    const auto start = std::chrono::steady_clock::now();
    const int samples = scene_.render.fogScatteredLightSamples;
    if (stale) {
        // A new bake; one in flight is dropped (its paths were for other values). A failure
        // leaves the cache stale, to be tried again.
        started_ = false;
        bakeSeconds_ = 0.0;
        if (bake_)
            startGpuBake();
        else
            bakeOnCpu();
        bakedKey_ = std::move(k);
        started_ = true;
    }
    if (bake_ && budgetMs_ > 0.0) {
        bake_->step(budgetMs_, samples);
    } else if (bake_) {
        const std::size_t cells = std::size_t(dims_.x) * dims_.y * dims_.z;
        ProgressNote note(fmt::format(
            "baking scattered-light cache on the GPU: {} cells x {} paths", cells, samples));
        while (!bake_->step(250.0, samples)) // a quarter second between progress updates
            note.set(bake_->fraction());
    }
    bakeSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (converging()) return;
    seconds_ = bakeSeconds_;
    ++bakes_;
    log::info("scattered-light cache: {}x{}x{} texels x {} paths baked on the {} in {:.2f} s{}",
              dims_.x, dims_.y, dims_.z, samples, bake_ ? "GPU" : "CPU", seconds_,
              bake_ && budgetMs_ > 0.0 ? " (progressive)" : "");
}

void ScatteredLightCache::bind(const gpu::Program& program) const {
    program.set("scatteredLo", glm::vec3(lo_)).set("scatteredHi", glm::vec3(hi_));
    (bake_ ? bake_->mean() : mean_).bind(VEIL_TEX_SCATTERED_LIGHT);
    (bake_ ? bake_->flux() : flux_).bind(VEIL_TEX_SCATTERED_LIGHT + 1);
}

double progressiveBakeMs(double budgetMs, double frameMs, double passesMs) {
    if (!(budgetMs > 0.0)) return 0.0;
    return std::max(budgetMs, frameMs - std::max(passesMs, 0.0));
}

} // namespace veil::volume
