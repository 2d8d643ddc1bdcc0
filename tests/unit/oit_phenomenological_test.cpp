// The CPU model of OIT `phenomenological` (src/oit/cpu/phenomenological.h) against closed
// forms: non-reflective colored glass gives exactly background * prod(1 - a + a t) ([McGuire16 Eq.
// 2], the Fig. 2 claim); one grey layer gives the exact over operator; the result does not depend
// on submission order; self-modulation only changes colored overlaps.
#include "oit/cpu/phenomenological.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace veil::test {

using oit::cpu::PhenomenologicalLayer;
using oit::cpu::phenomenologicalResolve;

namespace {
void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], tol) << "channel " << c;
}
} // namespace

TEST(OitPhenomenologicalModelTest, NonReflectiveColoredGlassIsExactProduct) {
    const glm::dvec3 bg(1.0, 0.9, 0.8);
    std::vector<PhenomenologicalLayer> layers = {
        {0.3, glm::dvec3(0.0), 1.0, {0.9, 0.25, 0.1}},
        {0.6, glm::dvec3(0.0), 0.7, {0.2, 0.7, 0.95}},
        {0.8, glm::dvec3(0.0), 0.4, {0.5, 0.5, 0.1}},
    };
    glm::dvec3 expected = bg;
    for (const auto& l : layers)
        expected *= glm::dvec3(1.0 - l.alpha) + l.alpha * l.transmission;
    expectNear(phenomenologicalResolve(layers, bg), expected, 1e-12);
}

TEST(OitPhenomenologicalModelTest, SingleGreyLayerIsTheOverOperator) {
    const glm::dvec3 bg(0.3, 0.6, 0.9), E(2.0, 1.0, 0.5);
    const double a = 0.6, t = 0.25;
    const std::vector<PhenomenologicalLayer> layers = {{0.7, a * E, a, glm::dvec3(t)}};
    // U = a E / (a (1 - t)); (1 - beta) U = a (1 - t) U = a E.
    expectNear(phenomenologicalResolve(layers, bg), a * E + (1 - a + a * t) * bg, 1e-12);
}

TEST(OitPhenomenologicalModelTest, OrderIndependent) {
    const glm::dvec3 bg(0.4, 0.45, 0.5);
    std::vector<PhenomenologicalLayer> layers = {
        {0.2, {0.1, 0.4, 0.15}, 0.5, {0.6, 0.6, 0.6}},
        {0.5, {0.63, 0.14, 0.14}, 0.7, {0.5, 0.1, 0.1}},
        {0.9, {0.06, 0.12, 0.54}, 0.6, {0.1, 0.3, 0.8}},
    };
    const glm::dvec3 first = phenomenologicalResolve(layers, bg);
    std::reverse(layers.begin(), layers.end());
    expectNear(phenomenologicalResolve(layers, bg), first, 1e-12);
    std::swap(layers[0], layers[1]);
    expectNear(phenomenologicalResolve(layers, bg), first, 1e-12);
}

TEST(OitPhenomenologicalModelTest, SelfModulationTintsColoredOverlapsOnly) {
    const glm::dvec3 bg(0.0);
    const std::vector<PhenomenologicalLayer> grey = {{0.5, glm::dvec3(0.5), 0.5, glm::dvec3(0.2)}};
    const std::vector<PhenomenologicalLayer> red = {{0.5, glm::dvec3(0.5), 0.5, {0.9, 0.1, 0.1}}};
    oit::cpu::PhenomenologicalOptions off;
    off.selfModulation = false;
    expectNear(phenomenologicalResolve(grey, bg), phenomenologicalResolve(grey, bg, off), 1e-12);
    // [McGuire17 Eq. 14]: channels where beta is below its maximum are darkened (green, blue here).
    const glm::dvec3 on = phenomenologicalResolve(red, bg),
                     plain = phenomenologicalResolve(red, bg, off);
    EXPECT_NEAR(on.r, plain.r, 1e-12);
    EXPECT_LT(on.g, plain.g - 0.01);
    EXPECT_LT(on.b, plain.b - 0.01);
}

} // namespace veil::test
