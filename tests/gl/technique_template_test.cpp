// A frame rendered with techniques assembled from the two templates: the OIT template
// (src/oit/_template) and the shadow template (src/shadows/_template), each registered with
// the one line a copy adds to its registry, and nothing else of the program changed: no file
// outside the templates' folders names them. The frame is checked against the analytic
// shading it did not produce (tests/gl/shadow_test_scenes.h, tests/support/analytic_shading.h):
// a directional light, an opaque caster over the floor and a non-casting transparent pane
// over another part of it. With the shadow template's strength s and the OIT template's
// opacity_scale k:
//   lit floor       ambient + E f cos                               (E f cos: the lit term)
//   shadowed floor  ambient + (1 - s) E f cos                        ([Williams78] with s)
//   under the pane  k a E f_pane cos + (1 - k a) (ambient + E f cos)  ([McGuire16 Eq. 2], T = 0)
#include "gl_fixture.h"

#include "base/error.h"
#include "frame/renderer.h"
#include "oit/_template/template.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "shadows/_template/template.h"
#include "shadows/technique.h"
#include "support/analytic_shading.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

// The pane: 2 x 2 at height 0.5 over (-2.5, -2.5), coverage 0.6, no transmission, base colour
// 0 (so only its GGX specular reflects, and no ambient), roughness 1; it casts no shadow.
constexpr double kPaneAlpha = 0.6, kPaneRoughness = 1.0, kPaneX = -2.5, kPaneZ = -2.5;

nlohmann::json templateScene(double strength, double opacityScale) {
    nlohmann::json doc = ss::base({{"type", "template"}, {"size", 1024}, {"strength", strength}});
    doc["render"]["oit"] = {{"type", "template"}, {"opacity_scale", opacityScale}};
    // The opaque caster: a 2 x 2 grey plane at height 1 over the origin.
    doc["objects"].push_back({{"name", "caster"},
                              {"shape", {{"type", "plane"}, {"size", {2, 2}}}},
                              {"material", "grey"},
                              {"transform", {{"translate", {0, 1, 0}}}}});
    doc["materials"]["pane"] = {{"base_color", 0.0},
                                {"roughness", kPaneRoughness},
                                {"alpha", kPaneAlpha},
                                {"transmission", 0.0}};
    doc["objects"].push_back({{"name", "pane"},
                              {"shape", {{"type", "plane"}, {"size", {2, 2}}}},
                              {"material", "pane"},
                              {"shadows", false},
                              {"transform", {{"translate", {kPaneX, 0.5, kPaneZ}}}}});
    return doc;
}

// The pane's reflected radiance: the light's irradiance times its specular lobe.
double paneRadiance() {
    const double s = 1.0 / std::sqrt(2.0);
    return ss::kIntensity *
           analytic::brdfCos(0.0, kPaneRoughness, {0, 1, 0}, {0, 1, 0}, {-s, s, 0});
}

} // namespace

class TechniqueTemplateGLTest : public GlTest {
protected:
    static void SetUpTestSuite() {
        GlTest::SetUpTestSuite();
        // The one line each technique adds to TechniqueKind::registerBuiltins() of its registry.
        if (!oit::Registry::instance().find("template"))
            oit::registerTemplate(oit::Registry::instance());
        if (!shadows::Registry::instance().find("template"))
            shadows::registerTemplate(shadows::Registry::instance());
    }

    // Renders the scene and checks the three points against the closed forms above.
    void expectAnalytic(double strength, double opacityScale) {
        SCOPED_TRACE(fmt::format("strength {}, opacity_scale {}", strength, opacityScale));
        const scene::Scene sc =
            scene::parseScene(templateScene(strength, opacityScale), sourceDir());
        frame::Renderer renderer(sc, info());
        ASSERT_EQ(renderer.technique().name(), "template");
        ASSERT_EQ(renderer.shadowTechnique().name(), "template");
        renderer.render();
        const ImageF img = renderer.readHdr();
        VEIL_EXPECT_NO_GL_ERROR();
        const double lit = ss::litFloor(), ambient = ss::ambient();
        const double a = kPaneAlpha * opacityScale;
        const struct {
            const char* what;
            double x, z, expected;
        } points[] = {
            {"lit floor", ss::kLitX, ss::kLitZ, ambient + lit},
            {"shadowed floor", ss::kShadowX, ss::kShadowZ, ambient + (1.0 - strength) * lit},
            {"floor under the pane", kPaneX, kPaneZ,
             a * paneRadiance() + (1.0 - a) * (ambient + lit)},
        };
        // The lighting test's bound: 3e-3 of the lit radiance (float32 BRDF, RGBA16F target).
        for (const auto& p : points)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(img.at(ss::px(p.x), ss::px(p.z), c), p.expected, 3e-3 * lit)
                    << p.what << ", channel " << c;
        EXPECT_EQ(renderer.shadowTechnique().stats()["strength"], strength);
        EXPECT_EQ(renderer.technique().stats()["opacity_scale"], opacityScale);
    }
};

TEST_F(TechniqueTemplateGLTest, FrameOfBothTemplatesIsTheAnalyticShading) {
    expectAnalytic(1.0, 1.0);  // the defaults: Williams shadows, the pane's own coverage
    expectAnalytic(0.25, 0.5); // both properties reach their shaders
}

TEST_F(TechniqueTemplateGLTest, ShadowTemplatePropertiesAreDeclared) {
    const shadows::TechniqueInfo* t = shadows::Registry::instance().find("template");
    ASSERT_NE(t, nullptr);
    for (const char* key : {"size", "max_lights", "bias", "pcf_radius", "strength"})
        EXPECT_NE(t->properties.find(key), nullptr) << key;
    EXPECT_THROW(shadows::Registry::instance().resolve("template", {{"strength", 2}}, "t"), Error);
}

// Adding a technique touches only its folder and one registry line: no source or shader
// outside the templates' own folders names them (the registration above is in this test).
TEST_F(TechniqueTemplateGLTest, NothingOutsideTheirFoldersNamesTheTemplates) {
    namespace fs = std::filesystem;
    const fs::path root = sourceDir();
    const fs::path own[] = {root / "src/oit/_template",          root / "src/shadows/_template",
                            root / "src/frame/stages/_template", root / "shaders/oit/_template",
                            root / "shaders/shadows/_template",  root / "shaders/frame/_template"};
    int files = 0;
    for (const char* dir : {"src", "shaders"})
        for (const auto& e : fs::recursive_directory_iterator(root / dir)) {
            if (!e.is_regular_file()) continue;
            bool inside = false;
            for (const fs::path& o : own)
                inside = inside || e.path().parent_path() == o;
            if (inside) continue;
            ++files;
            EXPECT_EQ(readTextFile(e.path()).find("_template"), std::string::npos) << e.path();
        }
    EXPECT_GT(files, 100);
}

} // namespace veil::test
