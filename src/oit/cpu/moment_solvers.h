// Polynomial root solvers for moment-based reconstructions [Munstermann18 secs. 4 and 5.3], double
// precision. Coefficients are given lowest degree first: c[0] + c[1] x + ... + c[n] x^n.
//
//   power moments (real roots):  m = 4 -> quadratic, m = 6 -> Blinn's cubic [Blinn07],
//                                m = 8 -> Neumark's quartic [Neumark65] whose resolvent
//                                cubic is solved by Blinn's cubic, root of smallest magnitude,
//                                with Herbison-Evans' adaptive factorization [Munstermann18
//                                sec. 4.2]
//   trigonometric (complex roots on the unit circle): the same formulas in complex arithmetic,
//                                avoiding cancellation in the quadratic by taking the root of
//                                greater magnitude, and Neumark with a resolvent root that is
//                                not of least magnitude [Munstermann18 sec. 5.3]
// The solvers assume the root structure the reconstruction guarantees (all roots real for
// power moments); where rounding breaks it (negative discriminants) they clamp to the nearest
// valid case instead of returning NaN. `polish` adds Newton steps on the original polynomial
// (the CPU reference uses them; the GLSL port does not).
#pragma once

#include <array>
#include <complex>

namespace veil::oit::cpu {

using Complex = std::complex<double>;

// Real roots of c0 + c1 x + c2 x^2 (c2 != 0); a negative discriminant is clamped to zero.
std::array<double, 2> solveQuadratic(const std::array<double, 3>& c);

// Blinn's cubic ([Blinn07], "How to solve a cubic equation, part 5"): the three real roots
// of c0 + c1 x + c2 x^2 + c3 x^3, the largest and smallest in magnitude each from the form
// that avoids cancellation, the middle one from the quadratic they span. When rounding makes
// the discriminant negative, it is clamped (a double root is returned).
std::array<double, 3> solveCubicBlinn(const std::array<double, 4>& c, bool polish = false);

// Neumark's quartic: four real roots of c0 + ... + c4 x^4 (c4 != 0).
std::array<double, 4> solveQuarticNeumark(const std::array<double, 5>& c, bool polish = false);

// Complex counterparts (any complex coefficients, leading one non-zero).
std::array<Complex, 2> solveQuadraticComplex(const std::array<Complex, 3>& c);
std::array<Complex, 3> solveCubicComplex(const std::array<Complex, 4>& c, bool polish = false);
std::array<Complex, 4> solveQuarticComplex(const std::array<Complex, 5>& c, bool polish = false);

} // namespace veil::oit::cpu
