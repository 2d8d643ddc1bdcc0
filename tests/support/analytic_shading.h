// Analytic shading references for GL tests, in double precision, written out from the
// formulas ([Walter07] GGX, height-correlated Smith, Schlick), independently of
// shaders/common/brdf.glsl: what a lit surface point must receive.
#pragma once

#include <algorithm>
#include <cmath>

namespace veil::test::analytic {

struct Vec {
    double x, y, z;
};
inline Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec normalize(Vec a) {
    const double l = std::sqrt(dot(a, a));
    return {a.x / l, a.y / l, a.z / l};
}

// f(l, v) * (n.l) for a dielectric (metalness 0) of albedo `albedo` and perceptual roughness r.
inline double brdfCos(double albedo, double r, Vec n, Vec v, Vec l) {
    const double pi = 3.14159265358979323846;
    const double nl = dot(n, l), nv = dot(n, v);
    if (nl <= 0) return 0;
    const Vec h = normalize(l + v);
    const double nh = dot(n, h), lh = dot(l, h);
    const double a = std::max(r * r, 1e-3), a2 = a * a;
    const double dd = nh * nh * (a2 - 1) + 1;
    const double D = a2 / (pi * dd * dd);
    const double gv = nl * std::sqrt(nv * nv * (1 - a2) + a2);
    const double gl = nv * std::sqrt(nl * nl * (1 - a2) + a2);
    const double V = 0.5 / (gv + gl);
    const double F = 0.04 + 0.96 * std::pow(1 - lh, 5);
    return ((1 - F) * albedo / pi + D * V * F) * nl;
}

} // namespace veil::test::analytic
