// One renderer for a frame range (sequence/prefetch.h RangeRenderer): frames that keep the
// scene's structure replace only the volumes' data, camera and lights, and each image equals a
// renderer built for that frame alone, bit for bit, with a temperature emission channel, a
// shadow-casting light and a turntable camera; a frame of another structure (the volume gone)
// builds a new renderer. Played with the next frame's upload behind the current frame's render
// (sequence/range_player.h), the images are the same, and the upload counters count each
// frame's volume data once. Frames held on the GPU (render.sequence_gpu_cache_mib) shown again
// upload nothing and give the same images; with the budget 0 every frame uploads.
#include "frame/renderer.h"
#include "gl_fixture.h"
#include "scene/timeline.h"
#include "sequence/prefetch.h"
#include "sequence/range_player.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

class RangeRendererTest : public GlTest {};

// The fire frames 1-4 glowing (temperature emission), a shadow-casting key, a turntable;
// 48x40 and few steps: cheap on llvmpipe.
scene::AnimatedScene fireRange(const std::string& after, const std::string& name,
                               int gpuCacheMiB = -1) {
    nlohmann::json volume = {
        {"name", "fire"},
        {"path", (dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_#.vdb").string()},
        {"grid", "flames"},
        {"density_scale", 6.0},
        {"temperature_grid", "temperature"},
        {"temperature_scale", 1100},
        {"temperature_offset", 900},
        {"after", after}};
    if (after == "blank") volume["frames"] = {1, 2};
    nlohmann::json doc = {
        {"render", {{"width", 48}, {"height", 40}, {"fog_steps", 40}, {"shadows", "opaque"}}},
        {"cameras",
         {{{"position", {0, -62, -98}},
           {"target", {0, 0, -112}},
           {"up", {0, 0, 1}},
           {"turntable", {{"frames", 8}, {"start_frame", 1}}}}}},
        {"lights", {{{"type", "directional"}, {"direction", {-0.4, 0.5, -0.75}}}}},
        {"volumes", {volume}}};
    if (gpuCacheMiB >= 0) doc["render"]["sequence_gpu_cache_mib"] = gpuCacheMiB;
    const fs::path file = writeTextFile(outputSubdir("range_renderer") / name, doc.dump());
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

} // namespace

TEST_F(RangeRendererTest, FramesReplacingVolumesEqualRenderersBuiltAlone) {
    const scene::AnimatedScene scene = fireRange("loop", "loop.json");
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    const std::vector<int> frames = {1, 2, 3, 4, 5};
    sequence::FramePrefetcher prefetcher(scene, frames, std::size_t(1) << 30, 2, max3D);
    sequence::RangeRenderer range(info(), {}, max3D);
    std::vector<gpu::ImageF> images;
    for (int f : frames) {
        sequence::PreparedFrame p = prefetcher.take();
        ASSERT_TRUE(p.error.empty()) << p.error;
        frame::Renderer& r = range.next(p);
        r.render();
        images.push_back(r.readHdr());
        const gpu::ImageF expected = alone(info(), scene, f);
        EXPECT_TRUE(samePixels(images.back(), expected)) << "frame " << f;
    }
    EXPECT_EQ(range.built(), 1);
    EXPECT_EQ(range.reused(), 4);
    EXPECT_FALSE(samePixels(images[0], images[1])); // the fire and the camera moved
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(RangeRendererTest, FrameOfAnotherStructureBuildsANewRenderer) {
    // Frames 1-2 of the files, then no volume at all.
    const scene::AnimatedScene scene = fireRange("blank", "blank.json");
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    const std::vector<int> frames = {1, 2, 3};
    sequence::FramePrefetcher prefetcher(scene, frames, std::size_t(1) << 30, 1, max3D);
    sequence::RangeRenderer range(info(), {}, max3D);
    for (int f : frames) {
        sequence::PreparedFrame p = prefetcher.take();
        ASSERT_TRUE(p.error.empty()) << p.error;
        frame::Renderer& r = range.next(p);
        r.render();
        EXPECT_TRUE(samePixels(r.readHdr(), alone(info(), scene, f))) << "frame " << f;
    }
    EXPECT_EQ(range.built(), 2);
    EXPECT_EQ(range.reused(), 1);
}

// The bytes of frame `frame`'s grid conversions as the upload sends them (half-float texels,
// 32-bit indirection entries), from a conversion made here.
static std::size_t frameUploadBytes(const scene::AnimatedScene& scene, int frame, int max3D) {
    const sequence::PreparedFrame p = sequence::prepareFrame(scene, frame, {}, max3D);
    std::size_t bytes = 0;
    for (const auto& g : p.grids)
        if (g.converted)
            bytes += g.converted->values.size() * 2 + g.converted->channel.size() * 2 +
                     g.converted->table.size() * 4;
    return bytes;
}

TEST_F(RangeRendererTest, UploadsBehindThePreviousRenderEqualRenderersBuiltAlone) {
    const scene::AnimatedScene scene = fireRange("loop", "loop.json");
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    const std::vector<int> frames = {1, 2, 3, 4};
    for (const bool overlap : {true, false}) {
        SCOPED_TRACE(overlap ? "overlapped" : "serial");
        sequence::RangePlayer player(scene, frames, info(), {}, std::size_t(1) << 30, 2, max3D,
                                     overlap);
        std::size_t replacedBytes = 0;
        for (int f : frames) {
            const sequence::PlayedFrame played = player.step();
            EXPECT_EQ(played.frame, f);
            // Read back after the next frame's volumes went up.
            EXPECT_TRUE(samePixels(played.renderer->readHdr(), alone(info(), scene, f)))
                << "frame " << f;
            EXPECT_EQ(played.uploadedAhead, overlap && f > 1) << "frame " << f;
            EXPECT_EQ(played.uploads, 1u) << "frame " << f;
            if (f > 1) {
                EXPECT_EQ(played.uploadedBytes, frameUploadBytes(scene, f, max3D)) << f;
                replacedBytes += played.uploadedBytes;
            }
        }
        EXPECT_TRUE(player.done());
        EXPECT_EQ(player.renderers().built(), 1);
        EXPECT_EQ(player.renderers().uploads(), frames.size());
        EXPECT_GT(replacedBytes, 0u);
    }
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(RangeRendererTest, HeldFramesShownAgainUploadNothing) {
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    // Frames 3 and 2 again, as the viewer's timeline scrubbing back.
    const std::vector<int> frames = {1, 2, 3, 4, 3, 2};
    for (const int cacheMiB : {-1, 0}) {
        SCOPED_TRACE(cacheMiB < 0 ? "default budget" : "budget 0");
        const scene::AnimatedScene scene =
            fireRange("loop", cacheMiB < 0 ? "held.json" : "held0.json", cacheMiB);
        sequence::RangePlayer player(scene, frames, info(), {}, std::size_t(1) << 30, 2, max3D);
        std::vector<gpu::ImageF> images;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const sequence::PlayedFrame played = player.step();
            ASSERT_EQ(played.frame, frames[i]);
            images.push_back(played.renderer->readHdr());
            const bool again = i >= 4;
            EXPECT_EQ(played.uploads, again && cacheMiB < 0 ? 0u : 1u) << "frame " << i;
            EXPECT_EQ(played.uploadedBytes == 0, again && cacheMiB < 0) << "frame " << i;
        }
        EXPECT_EQ(player.renderers().built(), 1);
        EXPECT_FALSE(samePixels(images[2], images[1]));
        EXPECT_TRUE(samePixels(images[4], images[2])) << "frame 3 shown again";
        EXPECT_TRUE(samePixels(images[5], images[1])) << "frame 2 shown again";
        EXPECT_TRUE(samePixels(images[5], alone(info(), scene, 2)));
    }
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
