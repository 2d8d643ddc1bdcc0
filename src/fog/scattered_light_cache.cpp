#include "fog/scattered_light_cache.h"

#include "base/error.h"
#include "base/log.h"
#include "base/progress.h"
#include "fog/gpu_volume.h"
#include "fog/scattered_light_bake.h"
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
    : scene_(scene), grids_(std::move(grids)) {
    PathTracerSettings settings;
    const VolumePathTracer tracer(scene_, grids_, settings);
    tracer.worldBounds(lo_, hi_);
    VEIL_CHECK(glm::all(glm::lessThan(lo_, hi_)),
               "scattered-light cache: the volumes have no bounds");
    dims_ = scatteredLightDims(scene_, grids_, lo_, hi_);
    const std::string& device = scene_.render.fogScatteredLightBake;
    const bool gpuBake =
        gpu.programs && (device == "gpu" || (device == "auto" && !softwareRenderer()));
    if (!gpuBake) return;
    for (const auto& g : grids_)
        gridMax_.push_back(double(openvdb::tools::minMax(g->tree()).max()));
    bake_ = std::make_unique<ScatteredLightBake>(*gpu.programs, std::move(gpu.defines),
                                                 std::move(gpu.bindVolumes));
}

ScatteredLightCache::~ScatteredLightCache() = default;

std::vector<float> ScatteredLightCache::key() const {
    std::vector<float> k{scene_.render.ambient.x, scene_.render.ambient.y, scene_.render.ambient.z,
                         float(scene_.render.seed)};
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

void ScatteredLightCache::ensure() {
    std::vector<float> k = key();
    if ((mean_ || bakes_ > 0) && k == bakedKey_) return;
    const auto start = std::chrono::steady_clock::now();
    const int samples = scene_.render.fogScatteredLightSamples;
    const std::size_t cells = std::size_t(dims_.x) * dims_.y * dims_.z;
    // Named on the progress line of a long render (base/progress.h), with an estimate.
    ProgressNote note(fmt::format("baking scattered-light cache on the {}: {} cells x {} paths",
                                  bake_ ? "GPU" : "CPU", cells, samples));
    if (bake_) {
        ScatteredLightBake::Setup setup;
        setup.lo = lo_;
        setup.hi = hi_;
        setup.dims = dims_;
        setup.samples = samples;
        setup.seed = scene_.render.seed;
        // The CPU bake's majorant (VolumePathTracer): sum of density_scale x the grid's largest.
        std::size_t g = 0;
        for (const auto& v : scene_.volumes)
            if (v.procedural != "homogeneous" && g < gridMax_.size())
                setup.majorant += double(v.densityScale) * std::max(0.0, gridMax_[g++]);
        bake_->start(scene_, setup);
        while (!bake_->step(250.0, samples)) // a quarter second between progress updates
            note.set(bake_->fraction());
    } else {
        PathTracerSettings settings;
        settings.seed = scene_.render.seed;
        const VolumePathTracer tracer(scene_, grids_, settings);
        const ScatteredLight s = tracer.scatteredLight(lo_, hi_, dims_, samples,
                                                       [&note](double done) { note.set(done); });
        mean_ = makeFilteredTexture3D(dims_, GL_RGBA32F, GL_RGBA, &s.mean[0].x);
        flux_ = makeFilteredTexture3D(dims_, GL_RGBA32F, GL_RGBA, &s.flux[0].x);
    }
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    bakedKey_ = std::move(k);
    ++bakes_;
    log::info("scattered-light cache: {}x{}x{} texels x {} paths baked on the {} in {:.2f} s",
              dims_.x, dims_.y, dims_.z, samples, bake_ ? "GPU" : "CPU", seconds_);
}

void ScatteredLightCache::bind(const gpu::Program& program) const {
    program.set("scatteredLo", glm::vec3(lo_)).set("scatteredHi", glm::vec3(hi_));
    (bake_ ? bake_->mean() : mean_).bind(VEIL_TEX_SCATTERED_LIGHT);
    (bake_ ? bake_->flux() : flux_).bind(VEIL_TEX_SCATTERED_LIGHT + 1);
}

} // namespace veil::volume
