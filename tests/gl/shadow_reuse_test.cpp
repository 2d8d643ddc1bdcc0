// Shadow map reuse (frame::Renderer::setReuseShadowMaps, docs/viewer.md "Slow drivers"): the
// viewer keeps the shadow technique's maps across frames while nothing they depend on changed.
// A frame that reuses them must equal a one-shot frame (reuse off: every pass runs) of the
// same camera and scene bit for bit: the same driver runs the same shaders on the same values,
// so the maps of the earlier frame are the maps this frame would draw, and any difference is
// a stale map. The pass counters (shadowMapRenders/Reuses) say whether the passes ran.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace veil::test {

namespace {

std::vector<std::uint8_t> rgba8(const gpu::Texture& t) {
    std::vector<std::uint8_t> v(std::size_t(t.width()) * t.height() * 4);
    glGetTextureImage(t.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(v.size()), v.data());
    return v;
}

// Mean of the R, G, B bytes (not alpha): a black frame has 0.
double meanRgb(const std::vector<std::uint8_t>& v) {
    double sum = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i)
        if (i % 4 != 3) sum += v[i];
    return sum / (double(v.size()) * 0.75);
}

// datasets/scenes/fog.json (a shadowed spot light, window slats, glass, a smoke volume) small
// enough for llvmpipe: 64 x 48 pixels, 128^2 maps; the techniques with the fog's optical-depth
// pass (src/shadows/common/fog_depth.h) get 32^2 fog columns instead of the default 128^2,
// which made them the slowest gl tests (30-33 s each in a loaded -j2 ctest run; 1.5-2 s alone
// now) and does not change what is tested (reuse across poses).
scene::Scene fogScene(const std::string& technique) {
    const bool fogDepth = technique == "stochastic" || technique == "stochastic-vsm" ||
                          technique == "transmittance-slicemap";
    return scene::loadScene(sourceDir() / "datasets/scenes/fog.json",
                            {"render.width=64", "render.height=48", "render.fog_steps=48",
                             "render.shadows={\"type\":\"" + technique + "\",\"size\":128" +
                                 (fogDepth ? ",\"fog_columns\":32" : "") + "}"});
}

// The scene camera turned by `yaw` radians about its target (an orbit, as the viewer's).
scene::Camera orbited(const scene::Camera& c, float yaw) {
    scene::Camera o = c;
    const glm::mat4 r = glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0.0f, 1.0f, 0.0f));
    o.position = c.target + glm::vec3(r * glm::vec4(c.position - c.target, 0.0f));
    return o;
}

frame::RendererOptions reuseOn() {
    frame::RendererOptions o;
    o.reuseShadowMaps = true;
    return o;
}

} // namespace

class ShadowReuseTest : public GlTest, public ::testing::WithParamInterface<const char*> {};

// Three orbit poses with reuse on (the second through the tiled refinement, as the viewer's
// full-size frames on llvmpipe): the shadow passes run once, and every frame equals the
// one-shot frame of the same camera exactly.
TEST_P(ShadowReuseTest, OrbitKeepsTheMapsAndEqualsOneShotFrames) {
    const scene::Scene s = fogScene(GetParam());
    frame::Renderer viewer(s, info(), reuseOn());
    frame::Renderer oneShot(s, info());
    ASSERT_FALSE(viewer.shadowTechnique().dependsOnCamera()) << GetParam();
    ASSERT_FALSE(viewer.shadowViews().empty() && viewer.shadowLights().viewCount == 0);
    const scene::Camera base = viewer.camera();
    std::vector<std::uint8_t> previous;
    for (int k = 0; k < 3; ++k) {
        const scene::Camera cam = orbited(base, 0.35f * float(k));
        viewer.setCamera(cam);
        if (k == 1) {
            viewer.beginRefinement(32);
            int steps = 0;
            while (!viewer.refineStep() && ++steps < 1000) {
            }
        } else {
            viewer.render();
        }
        oneShot.setCamera(cam);
        oneShot.render();
        const std::vector<std::uint8_t> got = rgba8(viewer.ldrTexture()),
                                        want = rgba8(oneShot.ldrTexture());
        EXPECT_TRUE(got == want) << GetParam() << ": pose " << k << " differs from one-shot";
        EXPECT_GT(meanRgb(got), 8.0) << "a black frame";
        if (k > 0) {
            EXPECT_FALSE(got == previous) << "the camera did not move the image";
        }
        previous = got;
        if (k == 1) {
            io::writeImage(outputDir() / (std::string("shadow-reuse-") + GetParam() + ".png"),
                           viewer.readLdr());
        }
    }
    EXPECT_EQ(viewer.shadowMapRenders(), 1u) << "the maps were drawn again for a camera move";
    EXPECT_EQ(viewer.shadowMapReuses(), 2u);
    EXPECT_EQ(oneShot.shadowMapRenders(), 3u) << "one-shot frames must draw their maps";
    EXPECT_EQ(oneShot.shadowMapReuses(), 0u);
    VEIL_EXPECT_NO_GL_ERROR();
}

INSTANTIATE_TEST_SUITE_P(CameraIndependent, ShadowReuseTest,
                         ::testing::Values("opaque", "moment", "stochastic",
                                           "transmittance-slicemap", "stochastic-vsm",
                                           "reference"));

class ShadowReuseEditTest : public GlTest {};

// A light edit (the session's sceneValuesChanged()) redraws the maps, and the frame equals a
// fresh renderer's of the edited scene (and differs from the frame before: the edit moved the
// shadows). A material edit (invalidateShadowMaps(), what the session calls for any live edit
// but exposure, tone map, background, ambient) redraws them too.
TEST_F(ShadowReuseEditTest, LightAndMaterialEditsRedrawTheMaps) {
    scene::Scene s = fogScene("moment");
    frame::Renderer viewer(s, info(), reuseOn());
    viewer.render();
    viewer.render();
    ASSERT_EQ(viewer.shadowMapRenders(), 1u);
    const std::vector<std::uint8_t> before = rgba8(viewer.ldrTexture());

    s.lights.at(0).position += glm::vec3(1.2f, 0.0f, 0.6f); // the spot light moves
    viewer.sceneValuesChanged();
    viewer.render();
    EXPECT_EQ(viewer.shadowMapRenders(), 2u) << "a light edit kept the old maps";
    const std::vector<std::uint8_t> afterLight = rgba8(viewer.ldrTexture());
    EXPECT_FALSE(afterLight == before) << "the light edit changed nothing";
    {
        frame::Renderer fresh(s, info());
        fresh.render();
        EXPECT_TRUE(afterLight == rgba8(fresh.ldrTexture())) << "stale maps after a light edit";
    }

    for (scene::Material& m : s.materials)
        if (m.name == "slat") m.baseColor = glm::vec3(0.9f, 0.1f, 0.1f);
    viewer.invalidateShadowMaps();
    viewer.render();
    EXPECT_EQ(viewer.shadowMapRenders(), 3u) << "a material edit kept the old maps";
    {
        frame::Renderer fresh(s, info());
        fresh.render();
        EXPECT_TRUE(rgba8(viewer.ldrTexture()) == rgba8(fresh.ldrTexture()));
    }

    // Shader reload and turning reuse on again start afresh as well.
    viewer.reloadShaders();
    viewer.render();
    EXPECT_EQ(viewer.shadowMapRenders(), 4u) << "a shader reload kept the old maps";
    viewer.render();
    EXPECT_EQ(viewer.shadowMapRenders(), 4u);
    VEIL_EXPECT_NO_GL_ERROR();
}

// `volume` shadows read the camera's depth (screen-space shadow volumes): with reuse on they
// are drawn every frame, and each frame equals the one-shot frame.
TEST_F(ShadowReuseEditTest, CameraDependentVolumeShadowsRedrawEveryFrame) {
    const scene::Scene s = fogScene("volume");
    frame::Renderer viewer(s, info(), reuseOn());
    frame::Renderer oneShot(s, info());
    ASSERT_TRUE(viewer.shadowTechnique().dependsOnCamera());
    const scene::Camera base = viewer.camera();
    for (int k = 0; k < 2; ++k) {
        const scene::Camera cam = orbited(base, 0.35f * float(k));
        viewer.setCamera(cam);
        viewer.render();
        oneShot.setCamera(cam);
        oneShot.render();
        EXPECT_TRUE(rgba8(viewer.ldrTexture()) == rgba8(oneShot.ldrTexture())) << "pose " << k;
    }
    EXPECT_EQ(viewer.shadowMapRenders(), 2u);
    EXPECT_EQ(viewer.shadowMapReuses(), 0u);
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
