// The scattered-light cache baked on the GPU (render.fog_scattered_light_bake gpu,
// docs/scattered-light.md): shaders/volume/cache_bake.comp, the CPU bake's estimator
// (integrators/path_tracer.h VolumePathTracer::scatteredLight) on the fog pass's density
// textures (gpu_volume.h), one invocation per texel, tracked against local majorants (a grid of
// them, integrators/majorant_grid.h, as the CPU tracer's). The work is split into dispatches
// of texels x samples: step() runs dispatches for a time budget, so a bake can be spread over
// frames (the viewer's progressive bake); the textures hold the P1 terms of the samples so far
// after every step. Texels that surfaces read with a small footprint get more samples in a
// second pass (Setup::surfaceTexels). Deterministic for a seed and sample count: every path's
// random numbers are keyed by (seed, texel, sample) and each texel adds its samples in order,
// whatever the split.
#pragma once

#include "gpu/objects.h"
#include "gpu/shader.h"
#include "integrators/path_tracer.h"
#include "scene/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace veil::volume {

class ScatteredLightBake {
public:
    // `defines`: the fog programs' VEIL_VOLUME_SLOTS (and VEIL_VOLUME_EMISSION where a volume
    // has an emission channel); `bindVolumes` binds the density textures and sets the volume
    // uniforms of volume_common.glsl (FogPass::bindVolumes) and the blackbody table.
    ScatteredLightBake(gpu::ProgramManager& programs, std::vector<std::string> defines,
                       std::function<void(const gpu::Program&)> bindVolumes);

    struct Setup {
        glm::dvec3 lo{0.0}, hi{0.0}; // the volumes' world box (ScatteredLightCache)
        glm::ivec3 dims{0};
        int samples = 0;
        std::uint32_t seed = 1;
        // The majorant grid over [lo, hi] (majorant_grid.h): extinction bounds, x fastest.
        glm::ivec3 majorantDims{0};
        std::vector<float> majorants;
        int maxBounces = 256, rouletteDepth = 8;
        // Texels that go on to `surfaceSamples` (> samples) after every texel has `samples`
        // (sorted; scatteredLightSurfaceTexels()): the surface pass.
        std::vector<std::uint32_t> surfaceTexels;
        int surfaceSamples = 0;
    };
    // Starts a bake of `scene`'s lights and ambient over `setup` (the textures are kept when
    // the grid is the same; their contents stand until the first step).
    void start(const scene::Scene& scene, const Setup& setup);
    // Dispatches until `budgetMs` of wall time (glFinish after each) has passed, at least one;
    // true when every sample is in. A dispatch aims at min(budgetMs, 100) ms from the measured
    // throughput: a pass of up to `batch` samples over every texel where that fits, else one
    // sample over part of them, never fewer than kMinDispatchCells texels (a GPU needs that many
    // invocations in flight; a smaller dispatch takes the time of its slowest paths whatever
    // its size, so its throughput would shrink the next one further).
    bool step(double budgetMs, int batch);
    static constexpr std::size_t kMinDispatchCells = 65536;
    bool done() const { return next_.sampleBegin >= passSamples(); }
    // Texel-samples done over texel-samples to do.
    double fraction() const;

    const gpu::Texture& mean() const { return mean_; }
    const gpu::Texture& flux() const { return flux_; }
    // The textures read back as the CPU bake's result (tests).
    ScatteredLight read() const;
    // Per texel the sample variance of the paths' luminance (tests: the Monte Carlo error).
    std::vector<double> luminanceVariance() const;
    int dispatches() const { return dispatches_; }

private:
    void dispatch(int cellBegin, int cellCount, int sampleBegin, int sampleEnd);
    // The pass in flight: 0 every texel to samples, 1 the surface texels to surfaceSamples.
    std::size_t passCells() const { return next_.pass == 0 ? cells_ : setup_.surfaceTexels.size(); }
    int passSamples() const { return next_.pass == 0 ? setup_.samples : setup_.surfaceSamples; }

    gpu::ProgramManager& programs_;
    gpu::ProgramHandle program_;
    std::function<void(const gpu::Program&)> bindVolumes_;
    const scene::Scene* scene_ = nullptr;
    Setup setup_;
    std::size_t cells_ = 0;
    gpu::Texture mean_{gpu::NoCreate}, flux_{gpu::NoCreate}, majorants_{gpu::NoCreate};
    gpu::Buffer accumulator_{gpu::NoCreate}, texels_{gpu::NoCreate};
    // The next dispatch: samples [sampleBegin, sampleEnd) of texels (of the pass) from
    // cellBegin on.
    struct Cursor {
        int sampleBegin = 0, sampleEnd = 0;
        std::size_t cellBegin = 0;
        int pass = 0;
    } next_;
    double cellSamplesPerMs_ = 0.0; // measured throughput (0: unknown)
    int dispatches_ = 0;
};

} // namespace veil::volume
