#include "fog/scattered_light_cache.h"

#include "base/error.h"
#include "base/log.h"
#include "fog/gpu_volume.h"
#include "integrators/path_tracer.h"

#include "shaders/common/bindings.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace veil::volume {

ScatteredLightCache::ScatteredLightCache(const scene::Scene& scene,
                                         std::vector<openvdb::FloatGrid::ConstPtr> grids)
    : scene_(scene), grids_(std::move(grids)) {
    PathTracerSettings settings;
    const VolumePathTracer tracer(scene_, grids_, settings);
    tracer.worldBounds(lo_, hi_);
    VEIL_CHECK(glm::all(glm::lessThan(lo_, hi_)),
               "scattered-light cache: the volumes have no bounds");
    dims_ = scatteredLightDims(scene_, grids_, lo_, hi_);
}

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
    if (mean_ && k == bakedKey_) return;
    PathTracerSettings settings;
    settings.seed = scene_.render.seed;
    const VolumePathTracer tracer(scene_, grids_, settings);
    const auto start = std::chrono::steady_clock::now();
    const ScatteredLight s =
        tracer.scatteredLight(lo_, hi_, dims_, scene_.render.fogScatteredLightSamples);
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    mean_ = makeFilteredTexture3D(dims_, GL_RGBA32F, GL_RGBA, &s.mean[0].x);
    flux_ = makeFilteredTexture3D(dims_, GL_RGBA32F, GL_RGBA, &s.flux[0].x);
    bakedKey_ = std::move(k);
    ++bakes_;
    log::info("scattered-light cache: {}x{}x{} texels x {} paths baked in {:.2f} s", dims_.x,
              dims_.y, dims_.z, s.samples, seconds_);
}

void ScatteredLightCache::bind(const gpu::Program& program) const {
    program.set("scatteredLo", glm::vec3(lo_)).set("scatteredHi", glm::vec3(hi_));
    mean_.bind(VEIL_TEX_SCATTERED_LIGHT);
    flux_.bind(VEIL_TEX_SCATTERED_LIGHT + 1);
}

} // namespace veil::volume
