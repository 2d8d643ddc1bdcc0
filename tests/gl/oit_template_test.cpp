// The technique template (src/oit/_template) stays a working technique: registered, it
// renders back-to-front planes as the exact composite (it blends like `blend`, which is exact
// in that order), its property reaches the shader, and the registry lists it.
#include "gl/gl_fixture.h"
#include "gl/oit_test_scenes.h"

#include "base/error.h"
#include "frame/renderer.h"
#include "oit/_template/template.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

namespace veil::test {

class OitTemplateGLTest : public GlTest {
protected:
    static void SetUpTestSuite() {
        GlTest::SetUpTestSuite();
        if (!oit::Registry::instance().find("template"))
            oit::registerTemplate(oit::Registry::instance());
    }
};

TEST_F(OitTemplateGLTest, RendersTheExactCompositeBackToFront) {
    // Back to front: blue at z = -1, then red at z = 1 (nearer the camera at z = 10).
    const std::vector<TestPlane> planes{{{0, 0, 1}, 0.5, {0.2, 0.9, 0.4}, -1.0},
                                        {{1, 0, 0}, 0.4, {0.8, 0.3, 0.1}, 1.0}};
    const glm::dvec3 bg(0.1, 0.6, 0.2);
    const scene::Scene sc = scene::parseScene(planeScene(planes, bg, 16, 16), sourceDir());
    std::vector<oit::cpu::Fragment> frags{planeFragment(planes[0]), planeFragment(planes[1])};
    const glm::dvec3 exact = oit::cpu::compositeSorted(frags, bg);

    frame::Renderer full(sc, info(), {16, 16, "", "template"});
    full.render();
    const ImageF img = full.readHdr();
    VEIL_EXPECT_NO_GL_ERROR();
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(img.at(8, 8, c), exact[c], 2e-3) << c; // RGBA16F rounding
    EXPECT_EQ(full.technique().stats()["opacity_scale"], 1.0);

    // opacity_scale 0: the planes vanish, the background stays.
    frame::Renderer none(sc, info(), {16, 16, "", "template", {{"opacity_scale", 0.0}}});
    none.render();
    const ImageF bare = none.readHdr();
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(bare.at(8, 8, c), bg[c], 1e-3) << c;
}

TEST_F(OitTemplateGLTest, PropertiesAreDeclared) {
    const oit::TechniqueInfo* t = oit::Registry::instance().find("template");
    ASSERT_NE(t, nullptr);
    ASSERT_NE(t->properties.find("opacity_scale"), nullptr);
    EXPECT_THROW(oit::Registry::instance().resolve("template", {{"opacity_scale", 2}}, "t"), Error);
}

} // namespace veil::test
