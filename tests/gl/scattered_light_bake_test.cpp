// The scattered-light cache baked on the GPU (src/fog/scattered_light_bake.h,
// shaders/volume/cache_bake.comp) against the CPU bake (the path tracer's
// VolumePathTracer::scatteredLight, itself checked against adding-doubling in
// tests/unit/path_tracer_test.cpp): the same estimator on the same texels, with other random
// numbers, float instead of double and the R16F density textures instead of the grid, so the
// two agree within their Monte Carlo error. The error of a texel's difference is
// sqrt(2 var / N), var the per-path sample variance of the luminance the GPU bake accumulates
// (both bakes draw from the same distribution), N paths per texel; the tolerance is 5 standard
// errors on the mean over all texels, and at most 2 % of the texels beyond 4 standard errors
// (a normal difference has 0.006 % there; 64-path means are skewed by rare bright paths, hence
// the margin). Also: the GPU bake is deterministic for a seed.
#include "gl_fixture.h"

#include "fog/fog_pass.h"
#include "fog/scattered_light_bake.h"
#include "fog/scattered_light_cache.h"
#include "frame/renderer.h"
#include "integrators/medium.h"
#include "integrators/path_tracer.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>

namespace veil::test {

namespace {

constexpr int kPaths = 64;

// A slab 1 x 0.5 x 1 (voxel 1/16, 2 voxels per texel: about 9 x 5 x 9 texels) lit by a sun
// and a point light, emitting, under a sky: every term of the estimator.
nlohmann::json bakeScene(const char* device, int seed, bool torus = false) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 8, "height": 8, "ambient": [0.10, 0.14, 0.20], "background": [0, 0, 0],
                 "fog_steps": 16, "fog_scattered_light": true, "fog_scattered_light_cell": 2},
      "cameras": [{"name": "c", "position": [0, 3, 3], "target": [0, 0, 0]}],
      "lights": [{"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 1.5},
                 {"type": "point", "position": [0.8, 0.6, 0], "intensity": 0.8,
                  "color": [1, 0.7, 0.4]}],
      "volumes": [{"procedural": "box", "size": [1, 0.5, 1], "voxel_size": 0.0625,
                   "density_scale": 3, "albedo": 0.85, "anisotropy": 0.5,
                   "emission": [0.05, 0.02, 0.0]}]})");
    if (torus) // a real grid: a torus of fog (values up to 100), densest in its core
        doc["volumes"][0] = {{"path", (dataDir() / "vdb-torus-fog/torus01.vdb").string()},
                             {"grid", "voxel_fog_density"},
                             {"transform", {{"scale", 0.05}}},
                             {"density_scale", 0.3},
                             {"albedo", 0.9},
                             {"anisotropy", 0.3}};
    doc["render"]["fog_scattered_light_samples"] = kPaths;
    doc["render"]["fog_scattered_light_bake"] = device;
    doc["render"]["seed"] = seed;
    return doc;
}

struct GpuResult {
    volume::ScatteredLight cache;
    std::vector<double> variance;
};

GpuResult bakeOnGpu(const gpu::ContextInfo& info, const scene::Scene& s) {
    frame::Renderer r(s, info, {0, 0, "", "blend"});
    r.render();
    const volume::ScatteredLightCache* cache = r.fog()->scatteredLightCache();
    EXPECT_TRUE(cache && cache->gpuBake());
    if (!cache || !cache->gpuBake()) return {};
    return {cache->gpuBake()->read(), cache->gpuBake()->luminanceVariance()};
}

const glm::dvec3 kLum(0.2126, 0.7152, 0.0722);

} // namespace

class ScatteredLightBakeTest : public GlTest {};

namespace {

// The GPU bake (local majorants) against the CPU bake (one majorant) on `s`.
void expectGpuMatchesCpu(const gpu::ContextInfo& info, const scene::Scene& s) {
    const GpuResult gpu = bakeOnGpu(info, s);
    ASSERT_FALSE(gpu.cache.mean.empty());
    ASSERT_EQ(gpu.cache.samples, kPaths);

    volume::PathTracerSettings settings;
    settings.seed = 7; // other random numbers than the GPU's anyway
    const volume::VolumePathTracer tracer(s, volume::loadMediumGrids(s), settings);
    const volume::ScatteredLight cpu =
        tracer.scatteredLight(gpu.cache.lo, gpu.cache.hi, gpu.cache.dims, kPaths);
    ASSERT_EQ(cpu.mean.size(), gpu.cache.mean.size());

    const std::size_t n = cpu.mean.size();
    double sumDiff = 0.0, sumVar = 0.0, sumCpu = 0.0, sumFluxDiff[3] = {0, 0, 0}, sumFluxVar = 0.0;
    std::size_t outliers = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double yg = glm::dot(glm::dvec3(gpu.cache.mean[i]), kLum);
        const double yc = glm::dot(glm::dvec3(cpu.mean[i]), kLum);
        const double var = 2.0 * gpu.variance[i] / kPaths; // of the difference
        sumDiff += yg - yc;
        sumVar += var;
        sumCpu += yc;
        if (std::abs(yg - yc) > 4.0 * std::sqrt(var) + 1e-6) ++outliers;
        // G = 3 mean(Y (-d)): per component var(3 Y d_k) <= 9 E[Y^2 d_k^2] = 3 E[Y^2] for
        // uniform d (a bound, so the flux's test is looser than the mean's).
        const double ey2 = gpu.variance[i] + yg * yg;
        for (int k = 0; k < 3; ++k)
            sumFluxDiff[k] += double(gpu.cache.flux[i][k]) - double(cpu.flux[i][k]);
        sumFluxVar += 2.0 * 3.0 * ey2 / kPaths;
    }
    const double meanDiff = sumDiff / n, se = std::sqrt(sumVar) / n;
    std::printf("GPU vs CPU bake, %zu texels x %d paths: mean luminance CPU %.5f, GPU - CPU "
                "%+.6f (standard error %.6f), %zu texels beyond 4 standard errors\n",
                n, kPaths, sumCpu / n, meanDiff, se, outliers);
    ASSERT_GT(sumCpu / n, 1e-3);
    EXPECT_LT(std::abs(meanDiff), 5.0 * se);
    EXPECT_LE(double(outliers), 0.02 * n);
    const double fluxSe = std::sqrt(sumFluxVar) / n;
    for (int k = 0; k < 3; ++k) {
        std::printf("flux G.%c: GPU - CPU %+.6f (bound on the standard error %.6f)\n", "xyz"[k],
                    sumFluxDiff[k] / n, fluxSe);
        EXPECT_LT(std::abs(sumFluxDiff[k] / n), 5.0 * fluxSe) << "xyz"[k];
    }
}

} // namespace

TEST_F(ScatteredLightBakeTest, GpuBakeMatchesTheCpuBakeWithinMonteCarloError) {
    expectGpuMatchesCpu(info(), scene::parseScene(bakeScene("gpu", 1), sourceDir()));
}

// On a real grid, whose majorant grid has empty cells, sparse ones and dense ones, and paths
// that cross many of them.
TEST_F(ScatteredLightBakeTest, GpuBakeMatchesTheCpuBakeOnARealGrid) {
    expectGpuMatchesCpu(info(), scene::parseScene(bakeScene("gpu", 2, true), sourceDir()));
}

// The same seed and sample count give the same cache bit for bit (another renderer, another
// bake); another seed another one.
TEST_F(ScatteredLightBakeTest, GpuBakeIsDeterministicForASeed) {
    const scene::Scene a = scene::parseScene(bakeScene("gpu", 3), sourceDir());
    const scene::Scene b = scene::parseScene(bakeScene("gpu", 4), sourceDir());
    const GpuResult first = bakeOnGpu(info(), a), again = bakeOnGpu(info(), a),
                    other = bakeOnGpu(info(), b);
    ASSERT_FALSE(first.cache.mean.empty());
    ASSERT_EQ(first.cache.mean.size(), again.cache.mean.size());
    std::size_t differ = 0, differOther = 0;
    for (std::size_t i = 0; i < first.cache.mean.size(); ++i) {
        differ += first.cache.mean[i] != again.cache.mean[i] ||
                  first.cache.flux[i] != again.cache.flux[i];
        differOther += first.cache.mean[i] != other.cache.mean[i];
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(differOther, first.cache.mean.size() / 2);
}

// fog_scattered_light_bake chooses the device: cpu has no GPU bake; gpu has one.
TEST_F(ScatteredLightBakeTest, PropertyChoosesTheDevice) {
    for (const char* device : {"cpu", "gpu"}) {
        const scene::Scene s = scene::parseScene(bakeScene(device, 1), sourceDir());
        frame::Renderer r(s, info(), {0, 0, "", "blend"});
        r.render();
        const volume::ScatteredLightCache* cache = r.fog()->scatteredLightCache();
        ASSERT_TRUE(cache);
        EXPECT_EQ(cache->bakesOnGpu(), std::string(device) == "gpu") << device;
        EXPECT_EQ(cache->bakes(), 1) << device;
    }
}

// The viewer's time for the progressive bake (progressiveBakeMs): the budget, or what the last
// frame's passes left of render.fog_scattered_light_frame_ms. Frames of 1000 ms on this tiny
// slab finish the bake in the first frame (the frames before have no passes); without the frame
// time (0) each frame takes the budget alone, one dispatch, and the bake spreads over frames.
TEST_F(ScatteredLightBakeTest, ProgressiveBakeFillsWhatThePassesLeaveOfTheFrame) {
    EXPECT_DOUBLE_EQ(volume::progressiveBakeMs(2.0, 25.0, 10.0), 15.0);
    EXPECT_DOUBLE_EQ(volume::progressiveBakeMs(2.0, 25.0, 24.0), 2.0);
    EXPECT_DOUBLE_EQ(volume::progressiveBakeMs(2.0, 0.0, 10.0), 2.0);
    EXPECT_DOUBLE_EQ(volume::progressiveBakeMs(0.0, 25.0, 10.0), 0.0); // the whole bake
    const scene::Scene s = scene::parseScene(bakeScene("gpu", 5), sourceDir());
    auto framesToConverge = [&](double frameMs) {
        frame::Renderer r(s, info(), {0, 0, "", "blend"});
        const volume::ScatteredLightCache* cache = r.fog()->scatteredLightCache();
        int frames = 0;
        do {
            double passes = 0.0;
            for (const auto& p : r.passTimes())
                passes += p.milliseconds;
            r.setScatteredLightBudgetMs(volume::progressiveBakeMs(1e-3, frameMs, passes));
            r.render();
            ++frames;
        } while (cache->converging() && frames < 10 * kPaths);
        EXPECT_FALSE(cache->converging());
        return frames;
    };
    EXPECT_EQ(framesToConverge(1000.0), 1);
    EXPECT_GT(framesToConverge(0.0), 4);
}

// The progressive bake (ScatteredLightCache::setBudgetMs, the viewer): a budget so small that
// every frame runs one dispatch; the frames draw with the paths so far, come closer to the
// full bake as they go, and end with the full bake's cache bit for bit (the same paths, each
// texel adding them in order). An edit (the light's intensity) starts it again: the next frame
// has few samples, and the end is the full bake of the edited scene.
TEST_F(ScatteredLightBakeTest, ProgressiveBakeConvergesToTheFullBake) {
    scene::Scene s = scene::parseScene(bakeScene("gpu", 5), sourceDir());
    const GpuResult full = bakeOnGpu(info(), s);
    ASSERT_FALSE(full.cache.mean.empty());

    frame::Renderer r(s, info(), {0, 0, "", "blend"});
    r.setScatteredLightBudgetMs(1e-3);
    const volume::ScatteredLightCache* cache = r.fog()->scatteredLightCache();
    ASSERT_TRUE(cache && cache->gpuBake());
    auto error = [&full](const volume::ScatteredLight& c) { // mean |Y - Y_full|
        double e = 0.0;
        for (std::size_t i = 0; i < c.mean.size(); ++i)
            e += std::abs(double(c.mean[i].w) - double(full.cache.mean[i].w));
        return e / double(c.mean.size());
    };
    std::vector<std::pair<int, double>> errors; // per frame before the end: paths, error
    int frames = 0;
    do {
        r.render();
        ++frames;
        const volume::ScatteredLight now = cache->gpuBake()->read();
        if (now.samples > 0 && now.samples < kPaths) errors.emplace_back(now.samples, error(now));
    } while (cache->converging() && frames < 10 * kPaths);
    std::printf("progressive bake: %d frames, %d dispatches\n", frames,
                cache->gpuBake()->dispatches());
    ASSERT_GE(errors.size(), 2u);
    std::printf("error against the full bake: %.5f at %d paths, %.5f at %d paths\n",
                errors.front().second, errors.front().first, errors.back().second,
                errors.back().first);
    EXPECT_GT(frames, 4); // it did spread over frames
    EXPECT_FALSE(cache->converging());
    EXPECT_EQ(cache->bakes(), 1);
    EXPECT_LT(errors.back().second, 0.5 * errors.front().second);
    const volume::ScatteredLight done = cache->gpuBake()->read();
    ASSERT_EQ(done.samples, kPaths);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < done.mean.size(); ++i)
        differ += done.mean[i] != full.cache.mean[i] || done.flux[i] != full.cache.flux[i];
    EXPECT_EQ(differ, 0u);

    // An edit: the light's intensity. The bake starts again and ends at the edited full bake.
    s.lights[0].intensity *= 2.0f;
    r.render();
    EXPECT_TRUE(cache->converging());
    EXPECT_LT(cache->gpuBake()->read().samples, kPaths);
    frames = 0;
    while (cache->converging() && frames < 10 * kPaths) {
        r.render();
        ++frames;
    }
    EXPECT_EQ(cache->bakes(), 2);
    const GpuResult edited = bakeOnGpu(info(), s);
    const volume::ScatteredLight after = cache->gpuBake()->read();
    ASSERT_EQ(after.mean.size(), edited.cache.mean.size());
    differ = 0;
    std::size_t changed = 0;
    for (std::size_t i = 0; i < after.mean.size(); ++i) {
        differ += after.mean[i] != edited.cache.mean[i];
        changed += after.mean[i] != done.mean[i];
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(changed, after.mean.size() / 2);
}

} // namespace veil::test
