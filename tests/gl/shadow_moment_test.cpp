// The `moment` shadow technique (src/shadows/moment) against a CPU double-precision
// evaluation of the same method: the casters' absorbance moments at the depths where the
// floor's shadow ray crosses them, reconstructed by [Munstermann18 Algorithm 2] with four power
// moments (src/oit/cpu/moments.h, the OIT's reference implementation, written from the paper and
// tested on its own) with the technique's bias and beta = 0; colour by the per-channel b0
// scaled by the mean absorbance's fraction in front (moment.h). What the analytic test
// (shadow_techniques_test.cpp) attributes to the method's bias is checked here exactly.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "oit/cpu/moments.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "support/test_support.h"

#include <glm/glm.hpp>

#include <cmath>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

struct Pane {
    double height, alpha;
    std::array<double, 3> t;
};

// Expected T per channel at the floor pixel of (kShadowX, kShadowZ) for panes over the origin.
std::array<double, 3> cpuMomentT(const frame::Renderer& renderer, const std::vector<Pane>& panes,
                                 double bias, double receiverOffset) {
    const shadows::LightView& v = renderer.shadowViews().at(0);
    // The floor point at the pixel centre and where its ray toward the light (-s, s, 0) meets
    // height h: x - h.
    const glm::dvec3 P(ss::centre(ss::px(ss::kShadowX)), 0.0, ss::centre(ss::px(ss::kShadowZ)));
    auto depth = [&](const glm::dvec3& q) {
        const double d = -(glm::dmat4(v.view) * glm::dvec4(q, 1.0)).z;
        return (d - v.nearPlane) / (double(v.farPlane) - v.nearPlane) * 2.0 - 1.0;
    };
    oit::cpu::Moments m({oit::cpu::MomentBasis::Power, 4});
    std::array<double, 3> b0{};
    for (const Pane& p : panes) {
        std::array<double, 3> a{};
        for (int c = 0; c < 3; ++c) {
            a[c] = -std::log(std::max(1.0 - p.alpha + p.alpha * p.t[c], 1e-7));
            b0[c] += a[c];
        }
        const double mean = (a[0] + a[1] + a[2]) / 3.0;
        oit::cpu::accumulate(m, depth(P + glm::dvec3(-p.height, p.height, 0.0)),
                             1.0 - std::exp(-mean), 0.0);
    }
    oit::cpu::MomentParams params;
    params.overestimation = 0.0;
    params.bias = bias;
    params.biasVector = {0.0, 0.375, 0.0, 0.375};
    const double zf = depth(P) - 2.0 * receiverOffset / (double(v.farPlane) - v.nearPlane);
    const double fraction = oit::cpu::absorbance(m, zf, params) / m.b0();
    return {std::exp(-fraction * b0[0]), std::exp(-fraction * b0[1]), std::exp(-fraction * b0[2])};
}

std::array<double, 3> gpuT(const ImageF& img) {
    std::array<double, 3> t{};
    const int lx = ss::px(ss::kLitX), ly = ss::px(ss::kLitZ);
    for (int c = 0; c < 3; ++c)
        t[c] = (img.at(ss::px(ss::kShadowX), ss::px(ss::kShadowZ), c) - ss::ambient()) /
               (img.at(lx, ly, c) - ss::ambient());
    return t;
}

} // namespace

class ShadowMomentTest : public GlTest {};

TEST_F(ShadowMomentTest, FloorTransmittanceEqualsTheCpuReconstruction) {
    // One pane, two coloured panes, four coverage layers; bias 6e-5 (the default) and a larger
    // 1e-3 whose leak is several times the tolerance, so the comparison sees the bias.
    const std::vector<std::vector<Pane>> stacks = {
        {{1.0, 1.0, {0.8, 0.5, 0.2}}},
        {{1.4, 1.0, {0.8, 0.6, 0.9}}, {1.0, 0.5, {0.2, 0.2, 0.2}}},
        {{1.0, 0.3, {0, 0, 0}},
         {1.08, 0.3, {0, 0, 0}},
         {1.16, 0.3, {0, 0, 0}},
         {1.24, 0.3, {0, 0, 0}}},
    };
    for (double bias : {6e-5, 1e-3}) {
        for (std::size_t k = 0; k < stacks.size(); ++k) {
            nlohmann::json doc =
                ss::base({{"type", "moment"}, {"size", 1024}, {"moment_bias", bias}});
            for (std::size_t i = 0; i < stacks[k].size(); ++i) {
                const Pane& p = stacks[k][i];
                ss::addPane(doc, "pane" + std::to_string(i), p.height, p.alpha,
                            {p.t[0], p.t[1], p.t[2]});
            }
            const scene::Scene sc = scene::parseScene(doc, sourceDir());
            frame::Renderer renderer(sc, info());
            renderer.render();
            const std::array<double, 3> got = gpuT(renderer.readHdr());
            const std::array<double, 3> want = cpuMomentT(renderer, stacks[k], bias, 0.02);
            double exact[3] = {1, 1, 1};
            for (const Pane& p : stacks[k])
                for (int c = 0; c < 3; ++c)
                    exact[c] *= 1.0 - p.alpha + p.alpha * p.t[c];
            for (int c = 0; c < 3; ++c) {
                // float32 moments and solve against double (the Hankel system is close to
                // singular: its pivot is ~bias x 0.375), RGBA16F output (2^-11): 1.5e-3.
                EXPECT_NEAR(got[c], want[c], 1.5e-3 * want[c])
                    << "stack " << k << ", bias " << bias << ", channel " << c << " (exact "
                    << exact[c] << ")";
            }
        }
    }
}

TEST_F(ShadowMomentTest, SmokeBallDarkensTheFloorByItsOpticalDepth) {
    // A density-4 ball of smoke over the floor: the floor in its shadow gets the transmittance
    // of the exact optical depth along the shadow ray within the media march's step error.
    // Through the centre of a ball of radius r and density sigma: tau = 2 r sigma.
    nlohmann::json doc = ss::base({{"type", "moment"}, {"size", 1024}, {"media_steps", 128}});
    const double r = 0.5, sigma = 1.0; // tau = 1 through the centre
    doc["volumes"].push_back({{"name", "ball"},
                              {"procedural", "sphere"},
                              {"size", 2 * r},
                              {"voxel_size", 0.02},
                              {"density_scale", sigma},
                              {"albedo", 0.0},
                              // centre at height 1 over (0.5, 0): its shadow centre is (1.5, 0)
                              {"transform", {{"translate", {ss::kShadowX - 1.0, 1.0, 0.0}}}}});
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    frame::Renderer renderer(sc, info());
    renderer.render();
    const std::array<double, 3> got = gpuT(renderer.readHdr());
    // The pixel centre is off the ray through the ball's centre by (0.031, 0.031) world:
    // chord length 2 sqrt(r^2 - d^2) with d the distance of that ray from the centre.
    const double dx = ss::centre(ss::px(ss::kShadowX)) - ss::kShadowX;
    const double dz = ss::centre(ss::px(ss::kShadowZ)) - ss::kShadowZ;
    const double d2 = dx * dx / 2.0 + dz * dz; // x offset seen across the 45-degree ray
    const double tau = 2.0 * std::sqrt(r * r - d2) * sigma;
    for (int c = 0; c < 3; ++c) // the 1%: voxel ramps at the ball's surface, 128 steps
        EXPECT_NEAR(got[c], std::exp(-tau), 1e-2 * std::exp(-tau)) << "channel " << c;
}

TEST_F(ShadowMomentTest, MediaMarchSkipsEmptyLeavesWithTheSameSums) {
    // Two balls of the previous test on the same (directional) shadow ray, 0.7 apart, so the
    // media march (media.comp) crosses empty leaves before, between and after them. Jumping
    // over them (media_skip_empty, the default) must give bit for bit the image of visiting
    // every step, and the floor is in a real shadow (both balls: T near exp(-2 tau) = 0.14).
    auto render = [&](bool skip) {
        nlohmann::json doc = ss::base(
            {{"type", "moment"}, {"size", 512}, {"media_steps", 256}, {"media_skip_empty", skip}});
        for (double h : {1.0, 2.2})
            doc["volumes"].push_back({{"name", "ball" + std::to_string(int(h * 10))},
                                      {"procedural", "sphere"},
                                      {"size", 1.0},
                                      {"voxel_size", 0.02},
                                      {"density_scale", 1.0},
                                      {"albedo", 0.0},
                                      {"transform", {{"translate", {ss::kShadowX - h, h, 0.0}}}}});
        const scene::Scene sc = scene::parseScene(doc, sourceDir());
        frame::Renderer renderer(sc, info());
        renderer.render();
        return renderer.readHdr();
    };
    const ImageF skipped = render(true), every = render(false);
    ASSERT_EQ(skipped.pixels.size(), every.pixels.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < skipped.pixels.size(); ++i)
        differing += skipped.pixels[i] != every.pixels[i];
    EXPECT_EQ(differing, 0u);
    const std::array<double, 3> t = gpuT(skipped);
    for (int c = 0; c < 3; ++c) // exp(-2) = 0.135; one ball alone would give 0.37
        EXPECT_LT(t[c], 0.2) << "channel " << c;
}

} // namespace veil::test
