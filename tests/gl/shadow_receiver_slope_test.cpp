// The opaque map's receiver-plane slope (render.shadows.receiver_slope, docs/shadows.md
// "opaque"): the floor of tests/gl/shadow_test_scenes.h lit at 45 degrees, seen from above,
// with a 512^2 map (texels of 0.022, wider than bias / 2): its unshadowed radiance (the
// lighting test's 3e-3: float32 BRDF, RGBA16F target) with the slope from the fragment's
// screen-space derivatives (the default), from projected tangents (`geometric`) and as one bias
// for every tap (`plane-bias`, the derivatives' slope times the kernel's reach); with
// `none` the taps beside each receiver meet the floor itself and it darkens (acne), which shows
// the switch the cost comparison of bench/sets/shadow-receiver-slope.json relies on; the same
// for a transparent film over the floor.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "support/test_support.h"

#include <cmath>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

// Mean radiance (red) over the 16 x 16 pixels around the lit point (-3, 3); `film`: under a
// transparent plane 5 mm above the floor (coverage 0.9, the floor's material), which the
// transparent pass shades (frame/transparent.frag) and which casts nothing into the opaque map.
double litFloorMean(const std::string& mode, const gpu::ContextInfo& info, bool film = false) {
    nlohmann::json doc = ss::base({{"type", "opaque"}, {"size", 512}, {"receiver_slope", mode}});
    if (film) {
        doc["materials"]["film"] = {
            {"base_color", 0.5}, {"roughness", 0.7}, {"metalness", 0}, {"alpha", 0.9}};
        doc["objects"].push_back({{"name", "film"},
                                  {"shape", {{"type", "plane"}, {"size", {8, 8}}}},
                                  {"material", "film"},
                                  {"transform", {{"translate", {0, 0.005, 0}}}}});
    }
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    frame::Renderer renderer(sc, info);
    renderer.render();
    const ImageF img = renderer.readHdr();
    double sum = 0.0;
    const int x0 = ss::px(ss::kLitX) - 8, y0 = ss::px(ss::kLitZ) - 8;
    for (int y = y0; y < y0 + 16; ++y)
        for (int x = x0; x < x0 + 16; ++x)
            sum += img.at(x, y, 0);
    return sum / 256.0;
}

} // namespace

class ShadowReceiverSlopeTest : public GlTest {};

TEST_F(ShadowReceiverSlopeTest, DerivativesAndGeometricLightTheTiltedFloor) {
    const double want = ss::ambient() + ss::litFloor();
    for (const char* mode : {"derivatives", "geometric", "plane-bias"})
        EXPECT_NEAR(litFloorMean(mode, info()), want, 3e-3 * want) << mode;
    EXPECT_LT(litFloorMean("none", info()), 0.95 * want) << "no slope, yet no acne";
}

// The mode reaches the transparent surfaces' programs too (it is compiled into every receiver,
// shadows::Technique::receivers): the film over the floor is lit alike with either slope, and
// darkens without it. Were the film's program left with the default slope, 0.9 of the pixel
// would stay lit under `none`.
TEST_F(ShadowReceiverSlopeTest, TransparentReceiversFollowTheMode) {
    const double lit = litFloorMean("derivatives", info(), true);
    EXPECT_NEAR(litFloorMean("geometric", info(), true), lit, 3e-3 * lit);
    EXPECT_NEAR(litFloorMean("plane-bias", info(), true), lit, 3e-3 * lit);
    EXPECT_LT(litFloorMean("none", info(), true), 0.95 * lit) << "no slope, yet no acne";
}

} // namespace veil::test
