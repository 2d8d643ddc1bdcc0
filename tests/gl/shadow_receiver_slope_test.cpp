// The opaque map's receiver-plane slope (render.shadows.receiver_slope, docs/shadows.md
// "opaque"): the floor of tests/gl/shadow_test_scenes.h lit at 45 degrees, seen from above,
// with a 512^2 map (texels of 0.022, wider than bias / 2): its unshadowed radiance (the
// lighting test's 3e-3: float32 BRDF, RGBA16F target) with the slope from the fragment's
// screen-space derivatives (the default) and from projected tangents (`geometric`); with
// `none` the taps beside each receiver meet the floor itself and it darkens (acne), which shows
// the switch the cost comparison of bench/sets/shadow-receiver-slope.json relies on.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "support/test_support.h"

#include <cmath>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

// Mean radiance (red) over the 16 x 16 pixels around the lit point (-3, 3).
double litFloorMean(const std::string& mode, const gpu::ContextInfo& info) {
    nlohmann::json doc = ss::base({{"type", "opaque"}, {"size", 512}, {"receiver_slope", mode}});
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
    for (const char* mode : {"derivatives", "geometric"})
        EXPECT_NEAR(litFloorMean(mode, info()), want, 3e-3 * want) << mode;
    EXPECT_LT(litFloorMean("none", info()), 0.95 * want) << "no slope, yet no acne";
}

} // namespace veil::test
