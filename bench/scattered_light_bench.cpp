// veil-bench --light-drag (scattered_light_bench.h).
#include "scattered_light_bench.h"

#include "bench_stats.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "fog/fog_pass.h"
#include "fog/scattered_light_bake.h"
#include "fog/scattered_light_cache.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "scene/scene.h"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>

namespace veil::bench {

namespace {

// Relative L1 error of `values` against `reference` (sum |a - r| / sum r) and the mean of
// |a - r| / r over the entries above 1 % of the reference's largest.
struct Error {
    double relL1 = 0.0, meanRel = 0.0;
};
Error relativeError(const std::vector<double>& values, const std::vector<double>& reference) {
    double diff = 0.0, sum = 0.0, top = 0.0, rel = 0.0;
    for (double r : reference)
        top = std::max(top, r);
    std::size_t n = 0;
    for (std::size_t i = 0; i < reference.size() && i < values.size(); ++i) {
        const double d = std::abs(values[i] - reference[i]);
        diff += d;
        sum += reference[i];
        if (reference[i] > 0.01 * top) {
            rel += d / reference[i];
            ++n;
        }
    }
    return {sum > 0.0 ? diff / sum : 0.0, n ? rel / double(n) : 0.0};
}

std::vector<double> cacheLuminance(const volume::ScatteredLightBake& bake) {
    const volume::ScatteredLight s = bake.read();
    std::vector<double> y(s.mean.size());
    for (std::size_t i = 0; i < y.size(); ++i)
        y[i] = s.mean[i].a;
    return y;
}

std::vector<double> frameLuminance(const frame::Renderer& renderer) {
    const gpu::ImageF image = renderer.readHdr();
    std::vector<double> y(image.pixels.size() / 4);
    for (std::size_t i = 0; i < y.size(); ++i)
        y[i] = 0.2126 * image.pixels[4 * i] + 0.7152 * image.pixels[4 * i + 1] +
               0.0722 * image.pixels[4 * i + 2];
    return y;
}

} // namespace

int lightDragBench(const LightDragOptions& o) {
    scene::Scene scene = scene::loadScene(o.scene, o.overrides);
    VEIL_CHECK(!scene.lights.empty(), "--light-drag: scene '{}' has no light to drag", o.scene);
    gpu::HeadlessContext context;
    frame::Renderer renderer(scene, context.info(), {o.width, o.height, {}, o.oit});
    const volume::FogPass* fog = renderer.fog();
    const volume::ScatteredLightCache* cache = fog ? fog->scatteredLightCache() : nullptr;
    VEIL_CHECK(cache && cache->bakesOnGpu(),
               "--light-drag: scene '{}' has no scattered-light cache baked on the GPU (set "
               "render.fog_scattered_light=true and render.fog_scattered_light_bake=gpu)",
               o.scene);
    const double budgetMs = scene.render.fogScatteredLightBudgetMs;
    VEIL_CHECK(budgetMs > 0.0,
               "--light-drag: render.fog_scattered_light_budget_ms is 0 (no progressive bake)");
    // The scene as opened: the whole bake before the first frame, as a drag starts from a
    // converged cache.
    renderer.setScatteredLightBudgetMs(0.0);
    renderer.render();
    glFinish();
    const double firstBakeMs = fog->scatteredLightBakeMs();
    for (int i = 0; i < o.warmup; ++i)
        renderer.render();
    glFinish();

    // The drag: the first light turns about the camera's up through its target every frame
    // (a light edit, as the viewer's panel makes it: Renderer::sceneValuesChanged), and each
    // frame runs the restarted bake for the budget, then the passes.
    // Each frame's bake time as the viewer gives it (fog/scattered_light_cache.h
    // progressiveBakeMs): the budget, or what the last frame's passes left of the frame time.
    const double frameMs = scene.render.fogScatteredLightFrameMs;
    auto passesMs = [&renderer] {
        double ms = 0.0;
        for (const auto& p : renderer.passTimes())
            ms += p.milliseconds;
        return ms;
    };
    auto setBakeMs = [&] {
        renderer.setScatteredLightBudgetMs(
            volume::progressiveBakeMs(budgetMs, frameMs, passesMs()));
    };
    const scene::Camera camera = renderer.camera();
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(float(o.degreesPerFrame)),
                                       glm::normalize(camera.up));
    std::map<std::string, std::vector<double>> samples;
    std::vector<std::string> order;
    std::vector<double> wall;
    for (int i = 0; i < o.frames; ++i) {
        scene::Light& light = scene.lights[0];
        light.direction = glm::normalize(glm::vec3(turn * glm::vec4(light.direction, 0.0f)));
        light.position =
            camera.target + glm::vec3(turn * glm::vec4(light.position - camera.target, 0.0f));
        renderer.sceneValuesChanged();
        setBakeMs();
        const auto t0 = Clock::now();
        renderer.render();
        glFinish();
        wall.push_back(msSince(t0));
        for (const auto& p : renderer.passTimes()) {
            if (!samples.count(p.name)) order.push_back(p.name);
            samples[p.name].push_back(p.milliseconds);
        }
    }
    nlohmann::json out;
    out["mode"] = "light drag with the progressive scattered-light bake (Renderer::render + "
                  "glFinish per frame, the bake's step included)";
    out["scene"] = o.scene;
    out["width"] = o.width;
    out["height"] = o.height;
    out["frames"] = o.frames;
    out["warmup"] = o.warmup;
    out["degrees_per_frame"] = o.degreesPerFrame;
    out["budget_ms"] = budgetMs;
    out["frame_ms"] = frameMs; // the bake fills the frame up to this (0: the budget alone)
    out["oit"] = renderer.oitName();
    out["renderer"] = context.info().renderer;
    out["first_bake_ms"] = firstBakeMs;
    out["cache_dims"] = {cache->dims().x, cache->dims().y, cache->dims().z};
    out["samples"] = scene.render.fogScatteredLightSamples;
    nlohmann::json passes = nlohmann::json::array();
    for (const auto& name : order)
        passes.push_back(passStats(name, samples[name]));
    passes.push_back(passStats("frame_wall", wall)); // the whole frame, the bake's step included
    out["drag_fps"] = 1000.0 / median(wall);
    out["drag_fraction_per_frame"] = cache->gpuBake()->fraction(); // of the last frame's bake

    if (o.converge) {
        // After the drag: frames go on with the bake in flight; at each time the cache and the
        // frame are read back (off the clock). Then the bake runs to its end: the converged
        // cache, the same whatever the split (seeded per texel and sample).
        std::vector<std::vector<double>> caches, frames;
        std::vector<double> at, fraction;
        std::vector<int> frameCount;
        double elapsed = 0.0;
        int count = 0;
        for (double t : o.times) {
            while (elapsed < 1e3 * t && cache->converging()) {
                setBakeMs();
                const auto t0 = Clock::now();
                renderer.render();
                glFinish();
                elapsed += msSince(t0);
                ++count;
            }
            at.push_back(elapsed / 1e3);
            fraction.push_back(cache->converging() ? cache->gpuBake()->fraction() : 1.0);
            frameCount.push_back(count);
            caches.push_back(cacheLuminance(*cache->gpuBake()));
            frames.push_back(frameLuminance(renderer));
        }
        renderer.setScatteredLightBudgetMs(0.0);
        const auto t0 = Clock::now();
        renderer.render();
        glFinish();
        const double finishMs = msSince(t0);
        const std::vector<double> cacheRef = cacheLuminance(*cache->gpuBake());
        const std::vector<double> frameRef = frameLuminance(renderer);
        nlohmann::json rows = nlohmann::json::array();
        for (std::size_t i = 0; i < o.times.size(); ++i) {
            const Error c = relativeError(caches[i], cacheRef),
                        f = relativeError(frames[i], frameRef);
            rows.push_back({{"t_s", o.times[i]},
                            {"measured_at_s", at[i]},
                            {"frames", frameCount[i]},
                            {"bake_fraction", fraction[i]},
                            {"cache_rel_l1", c.relL1},
                            {"cache_mean_rel", c.meanRel},
                            {"frame_rel_l1", f.relL1},
                            {"frame_mean_rel", f.meanRel}});
            // As pseudo-passes (percent, not ms) so that the run's tables show them.
            const double pct = 100.0 * c.relL1;
            passes.push_back({{"name", fmt::format("cache_error_pct_{:.2f}s", o.times[i])},
                              {"median_ms", pct},
                              {"min_ms", pct},
                              {"max_ms", pct}});
        }
        out["convergence"] = rows;
        out["convergence_note"] =
            "error against the converged cache (the bake in flight run to its end): cache_rel_l1 "
            "= sum |L - L_conv| / sum L_conv over the cache's texels (L: luminance of the mean "
            "radiance), *_mean_rel = mean |L - L_conv| / L_conv over entries above 1 % of the "
            "largest; frame_*: the same over the HDR frame's pixels (background included); "
            "times are the frames' wall clock after the drag, read-backs excluded";
        out["finish_bake_ms"] = finishMs;
    }
    out["passes"] = passes;
    const std::string text = out.dump(2);
    if (!o.json.empty())
        writeFileAtomically(o.json, [&](const std::filesystem::path& tmp) {
            std::ofstream f(tmp);
            f << text << "\n";
        });
    std::cout << text << "\n";
    return 0;
}

} // namespace veil::bench
