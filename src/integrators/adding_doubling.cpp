#include "integrators/adding_doubling.h"

#include "base/error.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace veil::volume {

namespace {

// Gauss-Legendre nodes and weights on [0, 1] (Newton's method on P_n).
void gaussLegendre01(int n, std::vector<double>& x, std::vector<double>& w) {
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            const double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-15) break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp); // half of the [-1, 1] weight
    }
}

// Dense n x n matrices, row-major.
using Mat = std::vector<double>;
using Vec = std::vector<double>;

Mat mul(const Mat& a, const Mat& b, int n) {
    Mat c(std::size_t(n) * n, 0.0);
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k) {
            const double aik = a[std::size_t(i) * n + k];
            for (int j = 0; j < n; ++j)
                c[std::size_t(i) * n + j] += aik * b[std::size_t(k) * n + j];
        }
    return c;
}

Vec mulv(const Mat& a, const Vec& v, int n) {
    Vec r(n, 0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            r[i] += a[std::size_t(i) * n + j] * v[j];
    return r;
}

// (I - m)^-1 by Gauss-Jordan elimination with partial pivoting.
Mat inverseOfIdentityMinus(const Mat& m, int n) {
    Mat a(std::size_t(n) * 2 * n, 0.0);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j)
            a[std::size_t(i) * 2 * n + j] = (i == j ? 1.0 : 0.0) - m[std::size_t(i) * n + j];
        a[std::size_t(i) * 2 * n + n + i] = 1.0;
    }
    for (int c = 0; c < n; ++c) {
        int p = c;
        for (int r = c + 1; r < n; ++r)
            if (std::abs(a[std::size_t(r) * 2 * n + c]) > std::abs(a[std::size_t(p) * 2 * n + c]))
                p = r;
        if (p != c)
            for (int j = 0; j < 2 * n; ++j)
                std::swap(a[std::size_t(p) * 2 * n + j], a[std::size_t(c) * 2 * n + j]);
        const double piv = a[std::size_t(c) * 2 * n + c];
        for (int j = 0; j < 2 * n; ++j)
            a[std::size_t(c) * 2 * n + j] /= piv;
        for (int r = 0; r < n; ++r) {
            if (r == c) continue;
            const double f = a[std::size_t(r) * 2 * n + c];
            if (f == 0.0) continue;
            for (int j = 0; j < 2 * n; ++j)
                a[std::size_t(r) * 2 * n + j] -= f * a[std::size_t(c) * 2 * n + j];
        }
    }
    Mat inv(std::size_t(n) * n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            inv[std::size_t(i) * n + j] = a[std::size_t(i) * 2 * n + n + j];
    return inv;
}

} // namespace

SlabReflectance addingDoublingSlab(double tau, double albedo, int nodes) {
    VEIL_CHECK(tau > 0.0 && std::isfinite(tau), "adding-doubling: optical thickness {} <= 0", tau);
    VEIL_CHECK(albedo >= 0.0 && albedo <= 1.0, "adding-doubling: albedo {} outside [0, 1]", albedo);
    const int n = nodes;
    std::vector<double> mu, w;
    gaussLegendre01(n, mu, w);
    // Operators act on flux fractions per direction bin: entry (i, j) is the fraction of the
    // flux arriving in bin j that leaves in bin i. A thin isotropically scattering layer sends
    // equal flux into equal solid angles (its radiance grows as 1/mu, its projected area
    // shrinks as mu): the fraction w_i / 2 of the scattered flux into bin i of either side.
    int doublings = 0;
    double d = tau;
    while (d > std::ldexp(1.0, -30)) {
        d *= 0.5;
        ++doublings;
    }
    Mat R(std::size_t(n) * n), T(std::size_t(n) * n);
    Vec r0(n), t0(n); // diffuse response to unit collimated flux at mu0 = 1
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            // Scattered fraction a d / mu_j; the unscattered part stays in its bin.
            const double s = albedo * d / mu[j] * 0.5 * w[i];
            R[std::size_t(i) * n + j] = s;
            T[std::size_t(i) * n + j] = s + (i == j ? 1.0 - d / mu[j] : 0.0);
        }
        r0[i] = albedo * d * 0.5 * w[i];
        t0[i] = r0[i];
    }
    double e = 1.0 - d; // the collimated beam's unscattered fraction (exp(-d) to first order)
    for (int k = 0; k < doublings; ++k) {
        // Two identical layers A (top) and B (bottom); the layer is symmetric, so reflection
        // and transmission from below equal those from above.
        const Mat inv = inverseOfIdentityMinus(mul(R, R, n), n); // (I - R_A R_B)^-1
        const Mat invT = mul(inv, T, n);
        // Collimated light: downward diffuse flux between the layers
        // d = (I - R R)^-1 (t0 + e R r0), upward u = e r0 + R d.
        Vec src = mulv(R, r0, n);
        for (int i = 0; i < n; ++i)
            src[i] = t0[i] + e * src[i];
        const Vec down = mulv(inv, src, n);
        Vec up = mulv(R, down, n);
        for (int i = 0; i < n; ++i)
            up[i] += e * r0[i];
        const Vec tu = mulv(T, up, n), td = mulv(T, down, n);
        Vec r2(n), t2(n);
        for (int i = 0; i < n; ++i) {
            r2[i] = r0[i] + tu[i];
            t2[i] = e * t0[i] + td[i];
        }
        // Diffuse operators: R2 = R + T (I - R R)^-1 R T, T2 = T (I - R R)^-1 T.
        const Mat R2 = [&] {
            Mat m = mul(T, mul(inv, mul(R, T, n), n), n);
            for (std::size_t q = 0; q < m.size(); ++q)
                m[q] += R[q];
            return m;
        }();
        T = mul(T, invT, n);
        R = R2;
        r0 = r2;
        t0 = t2;
        e *= e;
    }
    SlabReflectance out;
    for (int i = 0; i < n; ++i) {
        out.reflectance += r0[i];
        out.diffuseTransmittance += t0[i];
    }
    out.directTransmittance = std::exp(-tau);
    return out;
}

double chandrasekharH(double mu, double albedo) {
    const int n = 64;
    std::vector<double> x, w;
    gaussLegendre01(n, x, w);
    std::vector<double> h(n, 1.0);
    // H(mu) = 1 + (a/2) mu H(mu) int_0^1 H(mu') / (mu + mu') dmu', iterated in the form
    // 1/H(mu) = sqrt(1 - a) + (a/2) int_0^1 mu' H(mu') / (mu + mu') dmu', which converges for
    // a = 1 as well.
    auto evaluate = [&](double m, const std::vector<double>& hh) {
        double s = 0.0;
        for (int j = 0; j < n; ++j)
            s += w[j] * x[j] * hh[j] / (m + x[j]);
        return 1.0 / (std::sqrt(1.0 - albedo) + 0.5 * albedo * s);
    };
    for (int iter = 0; iter < 5000; ++iter) {
        std::vector<double> next(n);
        double change = 0.0;
        for (int i = 0; i < n; ++i) {
            next[i] = evaluate(x[i], h);
            change = std::max(change, std::abs(next[i] - h[i]));
        }
        h.swap(next);
        if (change < 1e-14) break;
    }
    return evaluate(mu, h);
}

} // namespace veil::volume
