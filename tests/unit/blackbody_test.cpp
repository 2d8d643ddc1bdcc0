// Blackbody colour (src/integrators/blackbody.h) against the Planckian locus of Krystek's rational
// approximation in CIE 1960 UCS [Krystek85] (|du|, |dv| < 1e-4 over 1000..15000 K), which
// shares nothing with the table integration.
#include "support/planckian_locus.h"
#include "integrators/blackbody.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace veil::test {

TEST(Blackbody, ChromaticityIsOnThePlanckianLocus) {
    for (double t : {1500.0, 2500.0, 4000.0, 6500.0, 10000.0}) {
        // Through linear sRGB and back, as a renderer's pixel is read.
        const glm::dvec2 xy = xyChromaticity(volume::linearSrgbToXyz(volume::blackbodyRgb(t)));
        const glm::dvec2 ref = krystekXy(t);
        EXPECT_NEAR(xy.x, ref.x, 0.005) << t << " K";
        EXPECT_NEAR(xy.y, ref.y, 0.005) << t << " K";
    }
}

TEST(Blackbody, RadianceFollowsPlanck) {
    // Wien's displacement: hotter is brighter at every wavelength; Y(2T) / Y(T) is large at
    // low T (visible band in Wien's tail) and tends to 2 (Rayleigh-Jeans) at very high T.
    EXPECT_GT(volume::blackbodyXyz(3000.0).y / volume::blackbodyXyz(1500.0).y, 50.0);
    const double hot = volume::blackbodyXyz(4e6).y / volume::blackbodyXyz(2e6).y;
    EXPECT_NEAR(hot, 2.0, 0.01);
    EXPECT_EQ(volume::blackbodyXyz(0.0), glm::dvec3(0.0));
}

TEST(Blackbody, TableInterpolatesTheIntegral) {
    // As shaders/volume/fog_medium.glsl reads it: linear interpolation in T of (rgb / Y, ln Y)
    // over 2048 entries to 25000 K (src/fog/fog_pass.cpp).
    const int n = 2048;
    const double maxKelvin = 25000.0;
    const std::vector<glm::vec4> table = volume::blackbodyTable(n, maxKelvin);
    ASSERT_EQ(table.size(), std::size_t(n));
    double worst = 0.0;
    for (double t = 1000.0; t <= 20000.0; t += 37.3) {
        const double u = t / maxKelvin * (n - 1);
        const int i = int(u);
        const double f = u - i;
        const glm::dvec4 c = glm::mix(glm::dvec4(table[i]), glm::dvec4(table[i + 1]), f);
        const glm::dvec3 rgb = glm::dvec3(c) * std::exp(c.w);
        const double y = volume::linearSrgbToXyz(rgb).y, yExact = volume::blackbodyXyz(t).y;
        worst = std::max(worst, std::abs(y / yExact - 1.0));
        const glm::dvec2 xy = xyChromaticity(volume::linearSrgbToXyz(rgb));
        const glm::dvec2 xyExact = xyChromaticity(volume::blackbodyXyz(t));
        EXPECT_NEAR(xy.x, xyExact.x, 1e-4) << t << " K";
        EXPECT_NEAR(xy.y, xyExact.y, 1e-4) << t << " K";
    }
    std::printf("blackbody table: worst relative Y error %.2e over 1000..20000 K\n", worst);
    EXPECT_LT(worst, 1e-3);
    EXPECT_EQ(table[0].w, -80.0f);
}

} // namespace veil::test
