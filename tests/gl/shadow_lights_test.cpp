// Shadows from every shadow-casting light (src/shadows/views.h): point lights through the six
// faces of a cube, several lights at once each with its own map, and the limits (more lights
// than max_lights, more views than VEIL_MAX_SHADOW_VIEWS) as errors, not silent drops. The
// expected radiance is analytic (tests/support/analytic_shading.h): a point in a light's
// shadow gets everything but that light, a lit point gets the BRDF response to all of them.
#include "gl_fixture.h"

#include "base/error.h"
#include "frame/renderer.h"
#include "scene/scene.h"
#include "support/analytic_shading.h"
#include "support/test_support.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace veil::test {

namespace {

using namespace analytic;

// 8x8 grey floor seen from straight above (orthographic, 128 px: 16 px per unit) with unit
// boxes standing on it at `boxes` (x, z centres).
nlohmann::json floorWithBoxes(const std::vector<std::pair<double, double>>& boxes,
                              nlohmann::json lights) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 128, "height": 128, "ambient": 0.1, "tonemap": "clamp",
                 "shadows": {"type": "opaque", "size": 1024, "pcf_radius": 1}},
      "cameras": [{"name": "top", "type": "orthographic", "position": [0, 10, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 8, "near": 1, "far": 20}],
      "materials": {"grey": {"base_color": 0.5, "roughness": 0.7, "metalness": 0}},
      "objects": [{"shape": {"type": "plane", "size": [8, 8]}, "material": "grey"}]})");
    for (const auto& [x, z] : boxes)
        doc["objects"].push_back({{"shape", {{"type", "box"}, {"size", {1, 1, 1}}}},
                                  {"material", "grey"},
                                  {"transform", {{"translate", {x, 0.5, z}}}}});
    doc["lights"] = std::move(lights);
    return doc;
}

int px(double x) { return static_cast<int>(std::floor((x + 4.0) / 8.0 * 128.0)); }
double centre(int p) { return -4.0 + (p + 0.5) * 8.0 / 128.0; }

const double kAmbient = 0.1 * 0.5;

// Radiance of the floor pixel nearest (x, z) from a point light at `l` of intensity I.
double pointLit(int ix, int iy, Vec l, double intensity) {
    const Vec d{l.x - centre(ix), l.y, l.z - centre(iy)};
    return intensity / dot(d, d) * brdfCos(0.5, 0.7, {0, 1, 0}, {0, 1, 0}, normalize(d));
}

} // namespace

class ShadowLightsTest : public GlTest {};

TEST_F(ShadowLightsTest, PointLightShadowsOnEveryCubeFace) {
    // A point light 2 above the centre and four boxes around it at distance 2: each box's
    // shadow falls on the floor behind it, seen through a different cube face (+x, -x, +z,
    // -z); the floor near the centre is lit through the -y face. Box at x in [1.5, 2.5]: the
    // floor at x = 3.5 sees the light through it (the ray crosses x = 2.5 at height 0.57).
    const Vec light{0, 2, 0};
    const nlohmann::json lights = nlohmann::json::array(
        {{{"type", "point"}, {"position", {0, 2, 0}}, {"intensity", 8.0}, {"shadows", true}}});
    const scene::Scene sc =
        scene::parseScene(floorWithBoxes({{2, 0}, {-2, 0}, {0, 2}, {0, -2}}, lights), sourceDir());
    frame::Renderer renderer(sc, info());
    renderer.render();
    const ImageF img = renderer.readHdr();
    VEIL_EXPECT_NO_GL_ERROR();
    ASSERT_EQ(renderer.shadowViews().size(), 6u);

    for (const auto& [x, z] :
         std::vector<std::pair<double, double>>{{3.5, 0}, {-3.5, 0}, {0, 3.5}, {0, -3.5}}) {
        const int ix = px(x), iy = px(z);
        EXPECT_NEAR(img.at(ix, iy, 1), kAmbient, 2e-3)
            << "in the shadow of the box toward (" << x << ", " << z << ")";
        // Beside the shadow (1.5 to the side): lit, the analytic point-light response.
        const int jx = px(x == 0 ? 1.5 : x), jy = px(z == 0 ? 1.5 : z);
        const double lit = kAmbient + pointLit(jx, jy, light, 8.0);
        EXPECT_NEAR(img.at(jx, jy, 1), lit, 3e-3 * lit)
            << "beside the shadow toward (" << x << ", " << z << ")";
    }
    // Under the light, through the -y face.
    const int cx = px(0.8), cy = px(0.8);
    const double lit = kAmbient + pointLit(cx, cy, light, 8.0);
    EXPECT_NEAR(img.at(cx, cy, 1), lit, 3e-3 * lit);
}

TEST_F(ShadowLightsTest, EveryShadowedLightHasItsOwnMap) {
    // Two directional lights at 45 degrees from +x and from -x and a spot light: one box in
    // the middle. The floor at x = +1 is in the shadow of the light travelling +x only, x = -1
    // of the other only; each receives the other light (and the spot) in full.
    const double s = 1.0 / std::sqrt(2.0);
    const nlohmann::json lights = nlohmann::json::array({{{"type", "directional"},
                                                          {"direction", {s, -s, 0}},
                                                          {"intensity", 1.0},
                                                          {"shadows", true}},
                                                         {{"type", "directional"},
                                                          {"direction", {-s, -s, 0}},
                                                          {"intensity", 2.0},
                                                          {"shadows", true}},
                                                         {{"type", "spot"},
                                                          {"position", {0, 6, 3}},
                                                          {"target", {0, 0, 3}},
                                                          {"outer_cone", 15},
                                                          {"inner_cone", 10},
                                                          {"intensity", 10.0},
                                                          {"shadows", true}}});
    const scene::Scene sc = scene::parseScene(floorWithBoxes({{0, 0}}, lights), sourceDir());
    frame::Renderer renderer(sc, info());
    renderer.render();
    const ImageF img = renderer.readHdr();
    ASSERT_EQ(renderer.shadowLights().lights, (std::vector<int>{0, 1, 2}));
    const Vec n{0, 1, 0}, v{0, 1, 0};
    const double fromMinusX = 1.0 * brdfCos(0.5, 0.7, n, v, {-s, s, 0}); // light 0
    const double fromPlusX = 2.0 * brdfCos(0.5, 0.7, n, v, {s, s, 0});   // light 1
    // The spot's cone (15 degrees at height 6 around z = 3: z in [1.4, 4.6]) misses the points.
    EXPECT_NEAR(img.at(px(1.0), px(0.0), 1), kAmbient + fromPlusX, 3e-3 * fromPlusX);
    EXPECT_NEAR(img.at(px(-1.0), px(0.0), 1), kAmbient + fromMinusX, 3e-3 * fromMinusX);
    // Unshadowed by both, outside the spot: both lights.
    EXPECT_NEAR(img.at(px(-2.5), px(-2.5), 1), kAmbient + fromMinusX + fromPlusX,
                3e-3 * (fromMinusX + fromPlusX));
}

TEST_F(ShadowLightsTest, TooManyShadowedLightsIsAnError) {
    nlohmann::json lights = nlohmann::json::array();
    for (int i = 0; i < 5; ++i)
        lights.push_back(
            {{"type", "directional"}, {"direction", {0.1 * i, -1, 0}}, {"shadows", true}});
    nlohmann::json doc = floorWithBoxes({{0, 0}}, lights);
    const scene::Scene five = scene::parseScene(doc, sourceDir());
    try {
        frame::Renderer renderer(five, info());
        FAIL() << "5 shadowed lights with max_lights 4 were accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("max_lights"), std::string::npos) << e.what();
    }
    // Raised limit: all five get a map.
    doc["render"]["shadows"]["max_lights"] = 5;
    const scene::Scene raised = scene::parseScene(doc, sourceDir());
    frame::Renderer renderer(raised, info());
    EXPECT_EQ(renderer.shadowLights().viewCount, 5);
    // Five point lights need 30 views, more than VEIL_MAX_SHADOW_VIEWS.
    for (auto& l : doc["lights"])
        l = {{"type", "point"}, {"position", {0, 3, 0}}, {"shadows", true}};
    doc["render"]["shadows"]["max_lights"] = 8;
    const scene::Scene points = scene::parseScene(doc, sourceDir());
    EXPECT_THROW({ frame::Renderer r(points, info()); }, Error);
}

TEST_F(ShadowLightsTest, UnknownTechniqueAndBadPropertiesNameThePlace) {
    nlohmann::json doc = floorWithBoxes({}, nlohmann::json::array());
    doc["render"]["shadows"] = {{"type", "nonesuch"}};
    try {
        frame::Renderer r(scene::parseScene(doc, sourceDir()), info());
        FAIL();
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("unknown shadow technique 'nonesuch'"), std::string::npos) << m;
        EXPECT_NE(m.find("opaque"), std::string::npos) << m; // lists the known ones
    }
    doc["render"]["shadows"] = {{"type", "opaque"}, {"size", 3}};
    try {
        frame::Renderer r(scene::parseScene(doc, sourceDir()), info());
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/render/shadows/size"), std::string::npos)
            << e.what();
    }
}

} // namespace veil::test
