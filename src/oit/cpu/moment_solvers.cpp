#include "oit/cpu/moment_solvers.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace veil::oit::cpu {

namespace {

// Newton steps on the original polynomial, kept only where they reduce the residual.
template <typename T, std::size_t N, std::size_t R>
void newtonPolish(const std::array<T, N>& c, std::array<T, R>& roots, int steps = 3) {
    auto eval = [&](T x, T& derivative) {
        T p = c[N - 1];
        derivative = T(0);
        for (std::size_t i = N - 1; i-- > 0;) {
            derivative = derivative * x + p;
            p = p * x + c[i];
        }
        return p;
    };
    for (T& r : roots) {
        for (int s = 0; s < steps; ++s) {
            T d;
            const T p = eval(r, d);
            if (std::abs(d) == 0.0) break;
            const T next = r - p / d;
            T dn;
            if (!(std::abs(eval(next, dn)) < std::abs(p))) break;
            r = next;
        }
    }
}

// The two roots (largest, smallest) of the depressed cubic t^3 + 3 cbar t + dbar = 0 with
// three real roots ([Munstermann18] via [Blinn07]): t_k = 2 sqrt(-cbar) cos(phi + 2 pi k / 3).
struct TrigRoots {
    double largest, smallest, middle;
};
TrigRoots depressedCubicRoots(double cbar, double dbar) {
    const double mc = std::max(-cbar, 0.0);
    const double m = std::sqrt(mc);
    const double phi =
        std::atan2(std::sqrt(std::max(4.0 * mc * mc * mc - dbar * dbar, 0.0)), -dbar) / 3.0;
    const double twoPiThird = 2.0 * std::numbers::pi / 3.0;
    return {2.0 * m * std::cos(phi), 2.0 * m * std::cos(phi + twoPiThird),
            2.0 * m * std::cos(phi + 2.0 * twoPiThird)};
}

} // namespace

std::array<double, 2> solveQuadratic(const std::array<double, 3>& c) {
    const double disc = std::max(c[1] * c[1] - 4.0 * c[2] * c[0], 0.0);
    const double t = -0.5 * (c[1] + std::copysign(std::sqrt(disc), c[1]));
    if (t == 0.0) return {0.0, 0.0}; // c1 = c0 = 0: double root at zero
    return {t / c[2], c[0] / t};
}

std::array<double, 3> solveCubicBlinn(const std::array<double, 4>& c, bool polish) {
    // Blinn's homogeneous form A x^3 + 3 B x^2 + 3 C x + D.
    const double A = c[3], B = c[2] / 3.0, C = c[1] / 3.0, D = c[0];
    const double d1 = A * C - B * B, d2 = A * D - B * C, d3 = B * D - C * C;
    // Large root from the A-form x = (t - B) / A: pick t with the larger |t - B|.
    const TrigRoots ta = depressedCubicRoots(d1, -2.0 * B * d1 + A * d2);
    const double tl =
        std::abs(ta.largest - B) >= std::abs(ta.smallest - B) ? ta.largest : ta.smallest;
    const double lt = tl - B, ls = A; // root lt / ls
    // Small root from the D-form (reversed polynomial) x = D / (t - C).
    const TrigRoots td = depressedCubicRoots(d3, -2.0 * C * d3 + D * d2);
    const double tsm =
        std::abs(td.largest - C) >= std::abs(td.smallest - C) ? td.largest : td.smallest;
    const double st = D, ss = tsm - C;
    // Middle root: the cubic is (E x^2 + F x + G)(Ms x - Mt).
    const double E = ls * ss, F = -lt * ss - ls * st, G = lt * st;
    const double mt = C * F - B * G, ms = C * E - B * F;
    std::array<double, 3> roots{lt / ls, ss != 0.0 ? st / ss : 0.0, ms != 0.0 ? mt / ms : -lt / ls};
    if (polish) newtonPolish(c, roots);
    return roots;
}

namespace {

// Neumark's factorization of x^4 + a x^3 + b x^2 + c x + d into (x^2 + G x + H)(x^2 + g x + h)
// for a given root y = G g of the resolvent cubic
//   y^3 - 2 b y^2 + (b^2 + a c - 4 d) y + (c^2 - a b c + a^2 d) = 0.
// There are two ways to get the factors, dividing by G - g or by H - h; as [HerbisonEvans95] we use
// both and keep the one that reproduces the coefficients best.
template <typename T>
void neumarkFactors(T a, T b, T c, T d, T y, T& G, T& g, T& H, T& h) {
    auto sqrtT = [](T v) {
        if constexpr (std::is_same_v<T, double>)
            return std::sqrt(std::max(v, 0.0));
        else
            return std::sqrt(v);
    };
    const T by = b - y;
    T s = sqrtT(a * a - 4.0 * y);
    T k = sqrtT(by * by - 4.0 * d);
    // Make a + s and by + k free of cancellation.
    if (std::real(std::conj(a) * s) < 0.0) s = -s;
    if (std::real(std::conj(by) * k) < 0.0) k = -k;
    auto error = [&](T G1, T g1, T H1, T h1) {
        return std::abs(G1 + g1 - a) + std::abs(G1 * g1 + H1 + h1 - b) +
               std::abs(G1 * h1 + g1 * H1 - c) + std::abs(H1 * h1 - d);
    };
    // (1) G, g = (a +- s) / 2, then H, h from G h + g H = c.
    T G1 = 0.5 * (a + s);
    T g1 = G1 != T(0) ? y / G1 : 0.5 * (a - s);
    T H1 = 0.5 * by, h1 = 0.5 * by;
    if (s != T(0)) {
        const T t = (a * by - 2.0 * c) / s;
        H1 = 0.5 * (by + t);
        h1 = 0.5 * (by - t);
    }
    if (std::abs(H1) >= std::abs(h1)) {
        if (H1 != T(0)) h1 = d / H1;
    } else {
        H1 = d / h1;
    }
    // (2) H, h = (by +- k) / 2, then G from G + g = a and G h + g H = c.
    const T H2 = 0.5 * (by + k);
    const T h2 = H2 != T(0) ? d / H2 : 0.5 * (by - k);
    const T G2 = h2 != H2 ? (c - a * H2) / (h2 - H2) : 0.5 * a;
    const T g2 = a - G2;
    const double e1 = error(G1, g1, H1, h1), e2 = error(G2, g2, H2, h2);
    if (e1 <= e2 || !std::isfinite(e2)) {
        G = G1, g = g1, H = H1, h = h1;
    } else {
        G = G2, g = g2, H = H2, h = h2;
    }
}

} // namespace

std::array<double, 4> solveQuarticNeumark(const std::array<double, 5>& q, bool polish) {
    const double a = q[3] / q[4], b = q[2] / q[4], c = q[1] / q[4], d = q[0] / q[4];
    const std::array<double, 3> ys =
        solveCubicBlinn({c * c - a * b * c + a * a * d, b * b + a * c - 4.0 * d, -2.0 * b, 1.0});
    // [Munstermann18 sec. 4.2]: the resolvent root of smallest magnitude.
    double y = ys[0];
    for (double v : ys)
        if (std::abs(v) < std::abs(y)) y = v;
    double G, g, H, h;
    neumarkFactors(a, b, c, d, y, G, g, H, h);
    const auto r1 = solveQuadratic({H, G, 1.0});
    const auto r2 = solveQuadratic({h, g, 1.0});
    std::array<double, 4> roots{r1[0], r1[1], r2[0], r2[1]};
    if (polish) newtonPolish(q, roots);
    return roots;
}

std::array<Complex, 2> solveQuadraticComplex(const std::array<Complex, 3>& c) {
    Complex s = std::sqrt(c[1] * c[1] - 4.0 * c[2] * c[0]);
    // [Munstermann18 sec. 5.3]: avoid cancellation by taking the root of greater magnitude first.
    if (std::real(std::conj(c[1]) * s) < 0.0) s = -s;
    const Complex t = -0.5 * (c[1] + s);
    if (t == Complex(0.0)) return {Complex(0.0), Complex(0.0)};
    return {t / c[2], c[0] / t};
}

std::array<Complex, 3> solveCubicComplex(const std::array<Complex, 4>& c, bool polish) {
    // Depressed t^3 + p t + q with x = t - a / 3 (Cardano), u^3 of greater magnitude.
    const Complex a = c[2] / c[3], b = c[1] / c[3], d = c[0] / c[3];
    const Complex p = b - a * a / 3.0;
    const Complex q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + d;
    Complex s = std::sqrt(q * q / 4.0 + p * p * p / 27.0);
    if (std::real(std::conj(-q) * s) < 0.0) s = -s;
    const Complex w = -0.5 * q + s;
    std::array<Complex, 3> roots;
    if (std::abs(w) == 0.0) {
        roots = {-a / 3.0, -a / 3.0, -a / 3.0}; // p = q = 0: triple root
    } else {
        const Complex u = std::exp(std::log(w) / 3.0);
        const Complex omega(-0.5, std::sqrt(3.0) / 2.0);
        Complex uk = u;
        for (int k = 0; k < 3; ++k) {
            roots[k] = uk - p / (3.0 * uk) - a / 3.0;
            uk *= omega;
        }
    }
    if (polish) newtonPolish(c, roots);
    return roots;
}

std::array<Complex, 4> solveQuarticComplex(const std::array<Complex, 5>& q, bool polish) {
    const Complex a = q[3] / q[4], b = q[2] / q[4], c = q[1] / q[4], d = q[0] / q[4];
    const std::array<Complex, 3> ys = solveCubicComplex(
        {c * c - a * b * c + a * a * d, b * b + a * c - 4.0 * d, -2.0 * b, Complex(1.0)}, true);
    // [Munstermann18 sec. 5.3]: a resolvent root that is not the one of least magnitude.
    Complex y = ys[0];
    for (const Complex& v : ys)
        if (std::abs(v) > std::abs(y)) y = v;
    Complex G, g, H, h;
    neumarkFactors(a, b, c, d, y, G, g, H, h);
    const auto r1 = solveQuadraticComplex({H, G, Complex(1.0)});
    const auto r2 = solveQuadraticComplex({h, g, Complex(1.0)});
    std::array<Complex, 4> roots{r1[0], r1[1], r2[0], r2[1]};
    if (polish) newtonPolish(q, roots);
    return roots;
}

} // namespace veil::oit::cpu
