// What is specific to the stochastic shadow techniques (src/shadows/stochastic): the [Enderton11]
// estimator is unbiased over seeds, the VSM's blur and Chebyshev bound are the formulas of
// [McGuire16 sec. 4.3] (checked against a double-precision CPU evaluation of the same maps), the
// stained glass colour ratio, and the caustic density of [McGuire16 Eq. 10-12]. Scenes: tests/gl/
// shadow_test_scenes.h (directional light along (s, -s, 0), floor seen from above).
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "shadows/stochastic/stochastic.h"
#include "support/test_support.h"

#include <glm/glm.hpp>

#include <cmath>
#include <vector>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

class StochasticShadowTest : public GlTest {
protected:
    static nlohmann::json technique(const std::string& name, nlohmann::json p) {
        p["type"] = name;
        p["size"] = 1024;
        p["samples"] = 4; // every driver here has 4; rho S integral below for S = 4
        return p;
    }
    // (floor radiance - ambient) / unshadowed radiance at world (x, 0, z), per channel.
    static std::array<double, 3> transmittance(const ImageF& img, double x, double z) {
        std::array<double, 3> t{};
        for (int c = 0; c < 3; ++c)
            t[c] = (img.at(ss::px(x), ss::px(z), c) - ss::ambient()) / ss::litFloor();
        return t;
    }
};

// Reads one RG32F array texture back (layer-major, then rows, then (m1, m2)).
std::vector<float> readMoments(const gpu::Texture& t) {
    std::vector<float> data(std::size_t(t.width()) * t.height() * t.depth() * 2);
    glGetTextureImage(t.id(), 0, GL_RG, GL_FLOAT, static_cast<GLsizei>(data.size() * 4),
                      data.data());
    return data;
}

} // namespace

// [Enderton11 sec. 3.2]: E[svis] = prod (1 - alpha_i). Three layers of coverage 0.3 (exact 0.343),
// one texel per lookup (filter_radius 0: the raw estimator), 8 seeds x 208 pixels reading distinct
// texels: the mean must be within 4 standard errors (measured) of the exact value, and the
// spread must be real noise no larger than the binomial sqrt(p (1 - p) / S).
TEST_F(StochasticShadowTest, EstimatorMeanMatchesExactOverSeeds) {
    const double exact = std::pow(0.7, 3);
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
        nlohmann::json doc = ss::base(technique("stochastic", {{"filter_radius", 0}}));
        doc["render"]["seed"] = seed;
        for (int i = 0; i < 3; ++i)
            ss::addPane(doc, "leaf" + std::to_string(i), 1.0 + 0.08 * i, 0.3, {0.0, 0.0, 0.0});
        const scene::Scene sc =
            scene::parseScene(doc, sourceDir()); // the renderer keeps a reference
        frame::Renderer renderer(sc, info());
        renderer.render();
        const ImageF img = renderer.readHdr();
        VEIL_EXPECT_NO_GL_ERROR();
        // The shadow of all three layers covers x in [0.16, 2], z in [-1, 1]; the camera sees
        // the floor directly (not through the layers) for x > 1.
        for (int py = ss::px(-0.5); py < ss::px(0.5); ++py)
            for (int px = ss::px(1.1); px < ss::px(1.9); ++px) {
                const double v = (img.at(px, py, 1) - ss::ambient()) / ss::litFloor();
                sum += v;
                sum2 += v * v;
                ++n;
            }
    }
    const double mean = sum / n;
    const double variance = (sum2 - n * mean * mean) / (n - 1);
    const double se = std::sqrt(variance / n);
    EXPECT_GT(std::sqrt(variance), 0.02) << "no noise: not a stochastic estimate";
    EXPECT_LE(std::sqrt(variance), std::sqrt(exact * (1 - exact) / 4) * 1.1)
        << "more noise than independent coin flips per sample";
    EXPECT_NEAR(mean, exact, 4.0 * se) << "mean over " << n << " lookups, SE " << se;
}

// [McGuire16 sec. 4.3]: moments blurred by a separable tent, read bilinearly, Chebyshev's bound
// with the light-bleeding linstep. Two planes from the light: coverage 0.5 at height 1.5 (R = 2 of
// 4 samples exactly) and ~1 at height 0.5 (t = 1e-6: all 4 samples), so every texel under both
// holds the depths {1.5: 1/2, 0.5: 1/2} and no noise. The GPU's blurred moments must equal the
// CPU's double-precision tent blur of the GPU's raw moments, and the floor's visibility the
// CPU's bilinear Chebyshev of those; the closed form is p = 0.25 / (0.25 + 1) = 0.2 (VSM light
// leaking through a plane that stops all light), remapped to (0.2 - 0.1) / 0.9.
TEST_F(StochasticShadowTest, VsmBlurAndChebyshevMatchCpuDouble) {
    const double bleeding = 0.1;
    nlohmann::json doc = ss::base(
        technique("stochastic-vsm",
                  {{"caustics", false}, {"light_bleeding", bleeding}, {"blur_radius", 10}}));
    ss::addPane(doc, "upper", 1.5, 1.0, {0.5, 0.5, 0.5});
    ss::addPane(doc, "lower", 0.5, 1.0, {1e-6, 1e-6, 1e-6});
    const scene::Scene sc = scene::parseScene(doc, sourceDir()); // the renderer keeps a reference
    frame::Renderer renderer(sc, info());
    renderer.render();
    const ImageF img = renderer.readHdr();
    VEIL_EXPECT_NO_GL_ERROR();
    const gpu::Texture* raw = renderer.resourceTexture("shadow.moments");
    const gpu::Texture* vsm = renderer.resourceTexture("shadow.vsm");
    ASSERT_TRUE(raw && vsm);
    const int N = raw->width(), layers = raw->depth();
    ASSERT_EQ(layers, 3); // one view, three channels
    const std::vector<float> m = readMoments(*raw), gpuBlur = readMoments(*vsm);
    const int r = shadows::stochasticVsmBlurTexels(10, N);
    ASSERT_EQ(r, 5);
    auto at = [&](const std::vector<double>& v, int l, int x, int y, int k) {
        x = std::clamp(x, 0, N - 1);
        y = std::clamp(y, 0, N - 1);
        return v[((std::size_t(l) * N + y) * N + x) * 2 + k];
    };
    std::vector<double> src(m.begin(), m.end()), tmp(src.size()), blur(src.size());
    for (int pass = 0; pass < 2; ++pass) {
        const std::vector<double>& from = pass == 0 ? src : tmp;
        std::vector<double>& to = pass == 0 ? tmp : blur;
        for (int l = 0; l < layers; ++l)
            for (int y = 0; y < N; ++y)
                for (int x = 0; x < N; ++x)
                    for (int k = 0; k < 2; ++k) {
                        double s = 0.0, w = 0.0;
                        for (int i = -r; i <= r; ++i) {
                            const double wi = r + 1 - std::abs(i);
                            s += wi *
                                 (pass == 0 ? at(from, l, x + i, y, k) : at(from, l, x, y + i, k));
                            w += wi;
                        }
                        to[((std::size_t(l) * N + y) * N + x) * 2 + k] = s / w;
                    }
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < blur.size(); ++i)
        worst = std::max(worst, std::abs(blur[i] - gpuBlur[i]));
    EXPECT_LT(worst, 2e-6) << "GPU tent blur vs CPU double";

    // A floor point in the shadow of both planes (x in [0.5, 1.5]) that the camera sees
    // directly (x > 1): its map uv and depth in double.
    const shadows::LightView& view = renderer.shadowViews().at(0);
    const int pxX = ss::px(1.25), pxZ = ss::px(0.0);
    const glm::dvec4 P(ss::centre(pxX), 0.0, ss::centre(pxZ), 1.0);
    const glm::dvec4 clip = glm::dmat4(view.viewProjection) * P;
    const glm::dvec2 uv = glm::dvec2(clip) / clip.w * 0.5 + 0.5;
    const double z =
        (-(glm::dmat4(view.view) * P).z - view.nearPlane) / (view.farPlane - view.nearPlane);
    const double sigmaMin = 0.01 / (view.farPlane - view.nearPlane); // bias 0.01 (default)
    const double tx = uv.x * N - 0.5, ty = uv.y * N - 0.5;
    const int x0 = static_cast<int>(std::floor(tx)), y0 = static_cast<int>(std::floor(ty));
    const double fx = tx - x0, fy = ty - y0;
    for (int c = 0; c < 3; ++c) {
        double mo[2];
        for (int k = 0; k < 2; ++k)
            mo[k] =
                (1 - fy) * ((1 - fx) * at(blur, c, x0, y0, k) + fx * at(blur, c, x0 + 1, y0, k)) +
                fy * ((1 - fx) * at(blur, c, x0, y0 + 1, k) + fx * at(blur, c, x0 + 1, y0 + 1, k));
        double p = 1.0;
        if (z > mo[0]) {
            const double var = std::max(mo[1] - mo[0] * mo[0], sigmaMin * sigmaMin);
            p = var / (var + (z - mo[0]) * (z - mo[0]));
        }
        const double expected = std::clamp((p - bleeding) / (1 - bleeding), 0.0, 1.0);
        const double measured = (img.at(pxX, pxZ, c) - ss::ambient()) / ss::litFloor();
        // half-float HDR target (1e-3 relative) and float texture filtering
        EXPECT_NEAR(measured, expected, 3e-3) << "channel " << c;
        EXPECT_NEAR(expected, (0.2 - bleeding) / (1 - bleeding), 1e-2)
            << "closed form of the two-plane bound, channel " << c;
    }
}

// Stained glass T = (0.75, 0.5, 0.25): rho = (0.25, 0.5, 0.75), R = rho S = 1, 2, 3 of S = 4
// samples exactly, so both techniques are noise-free here and the shadow's colour ratios must
// be the glass's, r/g = 1.5, g/b = 2, within 2%. (With a T where rho S is not an integer the
// ratio of `stochastic` carries the noise of cases() in shadow_techniques_test.cpp: e.g. 0.44
// relative on the 0.2 channel at PCF radius 4.)
TEST_F(StochasticShadowTest, StainedGlassColourRatio) {
    for (const char* name : {"stochastic", "stochastic-vsm"}) {
        nlohmann::json p = nlohmann::json::object();
        if (std::string(name) == "stochastic-vsm") p["caustics"] = false;
        nlohmann::json doc = ss::base(technique(name, p));
        ss::addPane(doc, "stained", 1.0, 1.0, {0.75, 0.5, 0.25});
        const scene::Scene sc =
            scene::parseScene(doc, sourceDir()); // the renderer keeps a reference
        frame::Renderer renderer(sc, info());
        renderer.render();
        const std::array<double, 3> t = transmittance(renderer.readHdr(), ss::kShadowX, 0.0);
        EXPECT_NEAR(t[0] / t[1], 1.5, 0.02 * 1.5) << name;
        EXPECT_NEAR(t[1] / t[2], 2.0, 0.02 * 2.0) << name;
        EXPECT_NEAR(t[1], 0.5, 0.01) << name;
    }
}

// [McGuire16 Eq. 10-12] on a grey pane (alpha 1, t = 0.5, ior 1.5) lit at 45 degrees: s = 0.25,
// g = 2 (1 - 0.7071^8) - 1 = 0.875, rho = (1 + g s^0.2) 0.5 = 0.8316, visibility 0.1684
// (instead of 0.5 without caustics). Noise: rho S = 3.33, 4 binomial SE over the tent of
// radius 5 (79 effective texels) = 0.084.
TEST_F(StochasticShadowTest, CausticDensityFollowsEq12) {
    nlohmann::json doc =
        ss::base(technique("stochastic-vsm", {{"blur_radius", 10}, {"caustics", true}}));
    ss::addPane(doc, "glass", 1.0, 1.0, {0.5, 0.5, 0.5});
    doc["materials"]["glass"]["ior"] = 1.5;
    const scene::Scene sc = scene::parseScene(doc, sourceDir()); // the renderer keeps a reference
    frame::Renderer renderer(sc, info());
    renderer.render();
    const std::array<double, 3> t = transmittance(renderer.readHdr(), ss::kShadowX, 0.0);
    const double s = 0.25, g = 2.0 * (1.0 - std::pow(std::sqrt(0.5), 128 * s * s)) - 1.0;
    const double rho = std::min((1.0 + g * std::pow(s, 0.2)) * 0.5, 1.0);
    const double expected = 1.0 - rho;
    const double tol = 4.0 * std::sqrt(expected * (1 - expected) / (4 * 79.0));
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(t[c], expected, tol) << "channel " << c;
}

} // namespace veil::test
