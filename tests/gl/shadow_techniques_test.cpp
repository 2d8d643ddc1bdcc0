// Every shadow technique against analytic transmittance (tests/gl/shadow_test_scenes.h): a
// pane of transmission T between the light and the floor gives T x the unshadowed radiance
// per channel, two panes T1 T2, n layers of coverage a give (1 - a)^n, a fog slab of optical
// depth tau gives exp(-tau). Each technique states its tolerance per case and why (its
// quantization, its filter, its sampling); `opaque` ignores transparent casters and fog by
// design, so it must give the unshadowed value, and the test says so.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "support/test_support.h"

#include <cmath>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

struct TechniqueCase {
    std::string name;
    nlohmann::json properties; // merged into {"type": name}
    // Relative tolerance of the floor radiance (minus ambient) against T x lit, per case; a
    // negative value: the technique ignores that kind of caster (expects T = 1).
    double pane, twoPanes, layers, fog;
    std::string why; // where the tolerances come from
};

std::ostream& operator<<(std::ostream& os, const TechniqueCase& c) { return os << c.name; }

std::vector<TechniqueCase> cases() {
    return {
        {"opaque",
         {},
         -1,
         -1,
         -1,
         -1,
         "Williams map of opaque casters only: transparent casters and fog cast nothing (the "
         "baseline); 2e-3 of float rounding"},
        {"transmittance-slicemap",
         {{"slices", 128}},
         2e-3,
         2e-3,
         2e-3,
         0.016,
         "003 sec. 3 slice counts: each pane is one slice (raster method) and the casters are "
         ">= 0.113 apart along the light, more than a uniform slice (11.36 / 128 = 0.089), so "
         "the counts and T_c^n are exact; left is the RGBA16F HDR target's rounding (2^-11 of "
         "ambient + T lit = 1.0e-3 of T at T = 0.2; measured <= 8.4e-4). Fog: per-slice "
         "optical depth with 4 midpoint samples per slice, a density edge is off by at most "
         "sigma x slice / 4 = 0.707 x 0.089 / 4 = 0.016 in tau, i.e. 1.6% of T (measured "
         "1.2e-4: the box's trilinear ramp is smooth)"},
    };
}

class ShadowTechniqueTest : public GlTest, public ::testing::WithParamInterface<TechniqueCase> {
protected:
    nlohmann::json shadows() const {
        nlohmann::json s =
            GetParam().properties.is_null() ? nlohmann::json::object() : GetParam().properties;
        s["type"] = GetParam().name;
        if (!s.contains("size")) s["size"] = 1024; // 512 gives acne on the 45-degree floor
        return s;
    }
    // Floor radiance at the shadow point minus ambient, over the unshadowed value, per channel.
    std::array<double, 3> measuredT(const nlohmann::json& doc) {
        const scene::Scene sc = scene::parseScene(doc, sourceDir());
        frame::Renderer renderer(sc, info());
        renderer.render();
        const ImageF img = renderer.readHdr();
        EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
        // The lit point must be unshadowed whatever the technique (a technique that darkens
        // everything would otherwise pass a dark shadow).
        const double lit = ss::litFloor();
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(img.at(ss::px(ss::kLitX), ss::px(ss::kLitZ), c), ss::ambient() + lit,
                        3e-3 * lit)
                << "lit floor, channel " << c;
        std::array<double, 3> t{};
        for (int c = 0; c < 3; ++c)
            t[c] = (img.at(ss::px(ss::kShadowX), ss::px(ss::kShadowZ), c) - ss::ambient()) / lit;
        return t;
    }
    void expectT(const std::array<double, 3>& measured, const std::array<double, 3>& expected,
                 double tolerance, const char* what) {
        for (int c = 0; c < 3; ++c) {
            const double want = tolerance < 0 ? 1.0 : expected[c];
            const double tol = tolerance < 0 ? 3e-3 : tolerance;
            EXPECT_NEAR(measured[c], want, tol * std::max(want, 0.05))
                << what << ", channel " << c << " (" << GetParam().why << ")";
        }
    }
};

} // namespace

TEST_P(ShadowTechniqueTest, PaneOfTransmissionT) {
    nlohmann::json doc = ss::base(shadows());
    ss::addPane(doc, "stained", 1.0, 1.0, {0.8, 0.5, 0.2});
    expectT(measuredT(doc), {0.8, 0.5, 0.2}, GetParam().pane, "one pane, T = (0.8, 0.5, 0.2)");
}

TEST_P(ShadowTechniqueTest, TwoPanesMultiply) {
    nlohmann::json doc = ss::base(shadows());
    ss::addPane(doc, "upper", 1.4, 1.0, {0.8, 0.6, 0.9});
    ss::addPane(doc, "lower", 1.0, 0.5, {0.2, 0.2, 0.2}); // lets 0.5 + 0.5 x 0.2 = 0.6 through
    expectT(measuredT(doc), {0.8 * 0.6, 0.6 * 0.6, 0.9 * 0.6}, GetParam().twoPanes,
            "two panes, T1 T2");
}

TEST_P(ShadowTechniqueTest, CoverageLayersGiveOneMinusAlphaToTheN) {
    nlohmann::json doc = ss::base(shadows());
    for (int i = 0; i < 4; ++i) // offset layers like stacked foliage cards
        ss::addPane(doc, "leaf" + std::to_string(i), 1.0 + 0.08 * i, 0.3, {0.0, 0.0, 0.0});
    const double t = std::pow(0.7, 4);
    expectT(measuredT(doc), {t, t, t}, GetParam().layers, "4 layers of coverage 0.3");
}

TEST_P(ShadowTechniqueTest, FogSlabGivesExpMinusTau) {
    nlohmann::json doc = ss::base(shadows());
    const double sigma = 1.0 / std::sqrt(2.0), thickness = 1.0; // tau = sigma sqrt(2) h = 1
    ss::addFogSlab(doc, sigma, thickness);
    const double t = std::exp(-1.0);
    expectT(measuredT(doc), {t, t, t}, GetParam().fog, "fog slab of optical depth 1");
}

INSTANTIATE_TEST_SUITE_P(Techniques, ShadowTechniqueTest, ::testing::ValuesIn(cases()),
                         [](const auto& info) {
                             std::string n = info.param.name;
                             for (char& c : n)
                                 if (c == '-') c = '_';
                             return n;
                         });

} // namespace veil::test
