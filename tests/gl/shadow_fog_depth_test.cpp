// Fog shadows at default properties against closed forms (docs/shadows-accuracy.md, "Fog
// shadows"): a homogeneous slab of fog (tests/gl/shadow_test_scenes.h addFogSlab, 1 thick,
// its bottom at height 1) over the floor, under a directional light (every ray to the light
// crosses it over sqrt(2)) and under a spot light at (-2, 4, 0) (the ray from a floor point
// P crosses it over |light - P| / 4), gives the floor T = exp(-sigma L) per pixel. T is the
// mean over a floor rectangle whose rays to the light cross the slab's top and bottom faces at
// least 0.2 from its sides (more than a fog column of the optical-depth map plus the density
// ramp), of the radiance over the same without the slab (no ambient light). The floor is 20 wide,
// so the light views are far deeper than the slab.
// - `transmittance-slicemap`, `stochastic`, `stochastic-vsm` read the shared optical-depth
//   map of the media (src/shadows/common/fog_depth.h): within 1 % at tau 0.25, sqrt(2), 3
//   (the bound derived in fog_depth.comp, plus the RGBA16F target's rounding);
// - `reference` marches each receiver's ray at its default media_steps (256), also with the
//   fog marcher at 256 steps per pixel, which needs the march split within llvmpipe's loop
//   budget: within 1e-3 of exp(-tau) on the tau sqrt(2) slab.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "support/test_support.h"

#include <glm/glm.hpp>

#include <cmath>
#include <map>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

constexpr int kPixels = 64; // over the 8 units of the floor

enum class Light { Directional, Spot };

nlohmann::json sceneDoc(const nlohmann::json& shadows, Light light) {
    nlohmann::json doc = ss::base(shadows);
    doc["render"]["width"] = kPixels;
    doc["render"]["height"] = kPixels;
    doc["render"]["fog_steps"] = 256;
    doc["render"]["ambient"] = 0.0; // T = radiance over the unshadowed radiance
    // A floor 20 wide (the camera sees its middle 8): light views about 28 deep, so the
    // default 128 slices x 4 substeps would put the depth samples 0.055 apart along the light.
    doc["objects"][0]["shape"]["size"] = {20.0, 20.0};
    if (light == Light::Spot)
        doc["lights"] = nlohmann::json::array({{{"type", "spot"},
                                                {"position", {-2, 4, 0}},
                                                {"target", {1, 0, 0}},
                                                {"inner_cone", 50},
                                                {"outer_cone", 60},
                                                {"intensity", 20},
                                                {"shadows", true}}});
    return doc;
}

struct Rect {
    double x0, x1, z0, z1;
};
Rect readRect(Light light) {
    // Directional: a floor point x reaches the slab's bottom at x - 1 and its top at x - 2;
    // spot: at x - (x + 2) / 4 and x - (x + 2) / 2, z scaled by 3/4 and 1/2.
    return light == Light::Directional ? Rect{1.4, 1.8, -0.5, 0.5} : Rect{1.1, 1.4, -0.4, 0.4};
}

// Path length through the slab (heights 1 to 2) of the ray from floor point (x, 0, z) to the
// light.
double pathLength(Light light, double x, double z) {
    if (light == Light::Directional) return std::sqrt(2.0);
    const glm::dvec3 d = glm::dvec3(-2.0, 4.0, 0.0) - glm::dvec3(x, 0.0, z);
    return glm::length(d) / d.y;
}

double centre(int p) { return -4.0 + (p + 0.5) * 8.0 / kPixels; }
int pixel(double x) { return static_cast<int>(std::floor((x + 4.0) / 8.0 * kPixels)); }

ImageF renderDoc(const nlohmann::json& doc, const gpu::ContextInfo& info) {
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    frame::Renderer renderer(sc, info);
    renderer.render();
    return renderer.readHdr();
}

struct Measured {
    double t = 0.0, want = 0.0, rounding = 0.0;
};

// The mean T over the rectangle (red channel: the slab is grey) and its closed form, for a slab
// of extinction sigma.
Measured measure(const nlohmann::json& shadows, Light light, double sigma,
                 const gpu::ContextInfo& info) {
    static std::map<int, ImageF> unshadowed;
    if (!unshadowed.count(int(light)))
        unshadowed[int(light)] =
            renderDoc(sceneDoc({{"type", "opaque"}, {"size", 512}}, light), info);
    const ImageF& lit = unshadowed[int(light)];
    nlohmann::json doc = sceneDoc(shadows, light);
    ss::addFogSlab(doc, sigma, 1.0);
    const ImageF img = renderDoc(doc, info);
    const Rect r = readRect(light);
    Measured m;
    int n = 0;
    for (int y = pixel(r.z0); y < pixel(r.z1); ++y)
        for (int x = pixel(r.x0); x < pixel(r.x1); ++x, ++n) {
            // RGBA16F rounds each radiance by up to 2^-11 of itself: T = img / lit moves by
            // up to 2^-11 (img + T lit) / lit = 2 T 2^-11.
            const double l = lit.at(x, y, 0), t = img.at(x, y, 0) / l;
            m.t += t;
            m.want += std::exp(-sigma * pathLength(light, centre(x), centre(y)));
            m.rounding += std::ldexp(2.0 * t, -11);
        }
    m.t /= n;
    m.want /= n;
    m.rounding /= n;
    return m;
}

// sigma giving optical depth tau at the rectangle's centre.
double sigmaFor(Light light, double tau) {
    const Rect r = readRect(light);
    return tau / pathLength(light, 0.5 * (r.x0 + r.x1), 0.5 * (r.z0 + r.z1));
}

const char* lightName(Light l) { return l == Light::Directional ? "directional" : "spot"; }

} // namespace

class ShadowFogDepthTest : public GlTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(ShadowFogDepthTest, SlabGivesExpMinusTauAtDefaults) {
    for (Light light : {Light::Directional, Light::Spot})
        for (double tau : {0.25, std::sqrt(2.0), 3.0}) {
            const Measured m =
                measure({{"type", GetParam()}, {"size", 512}}, light, sigmaFor(light, tau), info());
            EXPECT_NEAR(m.t, m.want, 1e-2 * m.want + m.rounding)
                << GetParam() << ", " << lightName(light) << " light, tau " << tau;
        }
}

INSTANTIATE_TEST_SUITE_P(FogDepthMap, ShadowFogDepthTest,
                         ::testing::Values("transmittance-slicemap", "stochastic",
                                           "stochastic-vsm"),
                         [](const auto& info) {
                             std::string n = info.param;
                             for (char& c : n)
                                 if (c == '-') c = '_';
                             return n;
                         });

// fog_slices 1024 x fog_substeps 64: 65536 density samples per column, past the 65535 loop
// iterations llvmpipe allows one invocation (before, one invocation marched them all and the
// optical depth stopped short: the floor came out lit). Marched in dispatches of 4096 samples,
// the map gives what 1024 x 4 samples give (both midpoint sums far finer than the slab's
// ramps; the same columns, so the same interpolation between them), within the RGBA16F
// target's rounding of the two images.
TEST_F(ShadowFogDepthTest, SamplesPastTheLoopLimitAreSplitAcrossDispatches) {
    const double sigma = sigmaFor(Light::Directional, std::sqrt(2.0));
    auto floorT = [&](int substeps) {
        return measure({{"type", "stochastic"},
                        {"size", 512},
                        {"fog_columns", 16},
                        {"fog_slices", 1024},
                        {"fog_substeps", substeps}},
                       Light::Directional, sigma, info());
    };
    const Measured fine = floorT(64), coarse = floorT(4);
    ASSERT_LT(coarse.t, 0.9) << "the slab casts no shadow";
    EXPECT_NEAR(fine.t, coarse.t, 2e-3 + fine.rounding + coarse.rounding);
}

TEST_F(ShadowFogDepthTest, ReferenceIsExactAtDefaultSteps) {
    // The default media_steps (256) per receiver and 256 fog steps per pixel: a midpoint sum of
    // 256 steps over the slab's smooth trilinear ramps is exact to far below 1e-3; what is left
    // is the RGBA16F target's rounding.
    for (Light light : {Light::Directional, Light::Spot}) {
        const Measured m = measure({{"type", "reference"}, {"size", 512}}, light,
                                   sigmaFor(light, std::sqrt(2.0)), info());
        EXPECT_NEAR(m.t, m.want, 1e-3) << lightName(light) << " light";
    }
}

TEST_F(ShadowFogDepthTest, ReferenceFogSamplesAtDefaultSteps) {
    // The fog marcher's samples march to the light too (256 fog steps x 256 media steps per
    // pixel at these settings): the scattering slab seen from the side (its centre pixel sees
    // in-scattered light only) as bright as with 64 media steps, which fit the loop budget
    // without the split. Both are midpoint sums over at most 0.71 of path across ramps 0.07
    // long: equal to far below the RGBA16F target's 2^-11 (x 2 for the two images).
    auto radiance = [&](int mediaSteps) {
        nlohmann::json doc = ss::stainedGlassOverFog(
            {{"type", "reference"}, {"size", 256}, {"media_steps", mediaSteps}});
        doc["objects"] = nlohmann::json::array();
        doc["render"]["width"] = 16;
        doc["render"]["height"] = 16;
        doc["render"]["fog_steps"] = 256;
        const ImageF img = renderDoc(doc, info());
        return img.at(img.width / 2, img.height / 2, 0);
    };
    const double exact = radiance(64), defaults = radiance(256);
    ASSERT_GT(exact, 1e-4) << "the slab is not lit at all";
    EXPECT_NEAR(defaults / exact, 1.0, 2.0 * std::ldexp(1.0, -11));
}

} // namespace veil::test
