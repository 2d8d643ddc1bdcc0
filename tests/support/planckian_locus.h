// The Planckian locus in CIE 1931 xy from Krystek's rational approximation in CIE 1960 UCS
// [Krystek85] (|du|, |dv| < 1e-4 over 1000..15000 K): a reference that shares nothing with the
// blackbody table's integration (src/integrators/blackbody.h), for the tests of both.
#pragma once

#include <glm/glm.hpp>

namespace veil::test {

inline glm::dvec2 krystekXy(double kelvin) {
    const double t = kelvin;
    const double u = (0.860117757 + 1.54118254e-4 * t + 1.28641212e-7 * t * t) /
                     (1.0 + 8.42420235e-4 * t + 7.08145163e-7 * t * t);
    const double v = (0.317398726 + 4.22806245e-5 * t + 4.20481691e-8 * t * t) /
                     (1.0 - 2.89741816e-5 * t + 1.61456053e-7 * t * t);
    const double d = 2.0 * u - 8.0 * v + 4.0;
    return {3.0 * u / d, 2.0 * v / d};
}

// x, y of a CIE 1931 XYZ colour.
inline glm::dvec2 xyChromaticity(const glm::dvec3& xyz) {
    const double s = xyz.x + xyz.y + xyz.z;
    return {xyz.x / s, xyz.y / s};
}

} // namespace veil::test
