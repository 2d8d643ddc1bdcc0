// The scattered-light cache over a frame range (sequence/prefetch.h RangeRenderer, the renderer
// of `veil render --frames` and veil-seqbench): one renderer for the range, the cache baked
// again only when a volume's data changed (FogPass::replaceVolume ->
// ScatteredLightCache::replaceGrid), kept when only the camera moved (a turntable over a static
// volume), and every frame equal bit for bit to a renderer built for that frame alone (the GPU
// bake is deterministic for its seed and sample count: a bake of the replaced grids equals a
// fresh one); with the viewer's progressive bake a frame with new data restarts the bake.
#include "fog/fog_pass.h"
#include "fog/scattered_light_cache.h"
#include "frame/renderer.h"
#include "gl_fixture.h"
#include "scene/timeline.h"
#include "sequence/prefetch.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

class ScatteredLightSequenceTest : public GlTest {};

// The ignition frames 1-4 of the EmberGen fire (7-9 K voxels) glowing (temperature emission),
// a sun, a sky, an 8-frame turntable; the cache on the GPU at 4 voxels per texel and 4 paths,
// 40x32 pixels: cheap on llvmpipe. `path` is the file pattern (a sequence) or one file.
scene::AnimatedScene fireRange(const std::string& path, const std::string& name) {
    const nlohmann::json doc = {
        {"render",
         {{"width", 40},
          {"height", 32},
          {"fog_steps", 32},
          {"ambient", {0.1, 0.12, 0.16}},
          {"fog_scattered_light", true},
          {"fog_scattered_light_samples", 4},
          {"fog_scattered_light_cell", 4},
          {"fog_scattered_light_bake", "gpu"}}},
        {"cameras",
         {{{"position", {0, -62, -98}},
           {"target", {0, 0, -112}},
           {"up", {0, 0, 1}},
           {"turntable", {{"frames", 8}, {"start_frame", 1}}}}}},
        {"lights", {{{"type", "directional"}, {"direction", {-0.4, 0.5, -0.75}}}}},
        {"volumes",
         {{{"name", "fire"},
           {"path", (dataDir() / "vdb-embergen-fire-seq" / path).string()},
           {"grid", "flames"},
           {"density_scale", 6.0},
           {"albedo", 0.8},
           {"temperature_grid", "temperature"},
           {"temperature_scale", 1100},
           {"temperature_offset", 900}}}}};
    const fs::path file =
        writeTextFile(outputSubdir("scattered_light_sequence") / name, doc.dump());
    return scene::loadAnimatedScene(file, {});
}

bool samePixels(const gpu::ImageF& a, const gpu::ImageF& b) {
    return a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

gpu::ImageF alone(const gpu::ContextInfo& context, const scene::AnimatedScene& scene, int frame) {
    const scene::Scene s = scene::sceneAtFrame(scene, frame);
    frame::Renderer r(s, context);
    r.render();
    return r.readHdr();
}

struct Played {
    std::vector<gpu::ImageF> images;
    std::vector<int> bakes; // the cache's bakes after each frame
    int built = 0, reused = 0;
};

Played play(const gpu::ContextInfo& context, const scene::AnimatedScene& scene,
            const std::vector<int>& frames) {
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    sequence::FramePrefetcher prefetcher(scene, frames, std::size_t(1) << 30, 1, max3D);
    sequence::RangeRenderer range(context, {}, max3D);
    Played out;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        sequence::PreparedFrame p = prefetcher.take();
        EXPECT_TRUE(p.error.empty()) << p.error;
        frame::Renderer& r = range.next(p);
        r.render();
        out.images.push_back(r.readHdr());
        const volume::ScatteredLightCache* cache =
            r.fog() ? r.fog()->scatteredLightCache() : nullptr;
        EXPECT_NE(cache, nullptr);
        out.bakes.push_back(cache ? cache->bakes() : -1);
    }
    out.built = range.built();
    out.reused = range.reused();
    return out;
}

} // namespace

// A turntable over one file: the camera alone moves, the range keeps its renderer and the
// cache of its first frame; each frame is the still render of that frame.
TEST_F(ScatteredLightSequenceTest, CameraOnlyFramesKeepTheCache) {
    const scene::AnimatedScene scene = fireRange("embergen_fire_a_4.vdb", "turntable.json");
    const std::vector<int> frames = {1, 2, 3};
    const Played p = play(info(), scene, frames);
    EXPECT_EQ(p.built, 1);
    EXPECT_EQ(p.reused, 2);
    EXPECT_EQ(p.bakes, (std::vector<int>{1, 1, 1})); // one bake for the range
    for (std::size_t i = 0; i < frames.size(); ++i)
        EXPECT_TRUE(samePixels(p.images[i], alone(info(), scene, frames[i])))
            << "frame " << frames[i];
    EXPECT_FALSE(samePixels(p.images[0], p.images[1])); // the camera moved
    VEIL_EXPECT_NO_GL_ERROR();
}

// A file sequence: every frame has other data, the cache is baked again for each, over the
// new grid's bounds and majorants, and equals the cache of a renderer built for the frame.
TEST_F(ScatteredLightSequenceTest, NewVolumeDataBakesAgainAsAFreshRenderer) {
    const scene::AnimatedScene scene = fireRange("embergen_fire_a_#.vdb", "sequence.json");
    const std::vector<int> frames = {2, 3, 4};
    const Played p = play(info(), scene, frames);
    EXPECT_EQ(p.built, 1);
    EXPECT_EQ(p.reused, 2);
    EXPECT_EQ(p.bakes, (std::vector<int>{1, 2, 3}));
    for (std::size_t i = 0; i < frames.size(); ++i)
        EXPECT_TRUE(samePixels(p.images[i], alone(info(), scene, frames[i])))
            << "frame " << frames[i];
    VEIL_EXPECT_NO_GL_ERROR();
}

// The viewer's rule (progressive bake, render.fog_scattered_light_budget_ms): a frame with new
// data restarts the bake, which runs one step per frame and ends in the frame's still render
// bit for bit; a frame where only the camera moved keeps the converged cache.
TEST_F(ScatteredLightSequenceTest, ProgressiveBakeRestartsOnNewDataOnly) {
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    for (const bool sequence : {true, false}) {
        const scene::AnimatedScene scene =
            sequence ? fireRange("embergen_fire_a_#.vdb", "progressive-sequence.json")
                     : fireRange("embergen_fire_a_4.vdb", "progressive-turntable.json");
        const std::vector<int> frames = {2, 3};
        sequence::FramePrefetcher prefetcher(scene, frames, std::size_t(1) << 30, 1, max3D);
        sequence::RangeRenderer range(info(), {}, max3D);
        for (int f : frames) {
            sequence::PreparedFrame p = prefetcher.take();
            ASSERT_TRUE(p.error.empty()) << p.error;
            frame::Renderer& r = range.next(p);
            r.setScatteredLightBudgetMs(0.001); // one dispatch (one path per texel) a frame
            r.render();
            const volume::ScatteredLightCache* cache = r.fog()->scatteredLightCache();
            // The first frame bakes; the second only with new data.
            EXPECT_EQ(cache->converging(), f == 2 || sequence) << "frame " << f;
            int steps = 1;
            while (cache->converging() && steps < 100) {
                r.render();
                ++steps;
            }
            EXPECT_FALSE(cache->converging());
            EXPECT_EQ(cache->bakes(), f == 2 || !sequence ? 1 : 2) << "frame " << f;
            EXPECT_TRUE(samePixels(r.readHdr(), alone(info(), scene, f))) << "frame " << f;
        }
    }
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
