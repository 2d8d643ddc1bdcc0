#include "oit/cpu/moments.h"

#include "base/error.h"
#include "oit/cpu/moment_solvers.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace veil::oit::cpu {

std::string MomentSet::name() const {
    return fmt::format("{}{}", basis == MomentBasis::Power ? 'p' : 't', count);
}

MomentParams defaultMomentParams(MomentSet set, bool storage16) {
    MomentParams p;
    // docs/oit.md#moment-constants table "Overall bias", verified by
    // tests/unit/oit_moment_test.cpp.
    if (set.basis == MomentBasis::Power) {
        VEIL_CHECK(set.count == 4 || set.count == 6 || set.count == 8,
                   "power moments: count must be 4, 6 or 8 (got {})", set.count);
        if (set.count == 4) {
            p.bias = storage16 ? 6e-5 : 5e-7;
            p.biasVector = storage16 ? std::vector<double>{0, 0.628, 0, 0.628}
                                     : std::vector<double>{0, 0.375, 0, 0.375};
        } else if (set.count == 6) {
            p.bias = storage16 ? 6e-4 : 5e-6;
            p.biasVector = storage16 ? std::vector<double>{0, 0.5566, 0, 0.489, 0, 0.47869382}
                                     : std::vector<double>{0, 0.48, 0, 0.451, 0, 0.45};
        } else {
            p.bias = storage16 ? 2.5e-3 : 5e-5;
            p.biasVector = storage16
                               ? std::vector<double>{0, 0.42474916387959866, 0, 0.22407802675585284,
                                                     0, 0.15369230769230768, 0, 0.12900440529089119}
                               : std::vector<double>{0, 0.75, 0, 0.676666666666667,
                                                     0, 0.63, 0, 0.600303030303030};
        }
    } else {
        VEIL_CHECK(set.count >= 2 && set.count <= 4,
                   "trigonometric moments: count must be 2, 3 or 4 (got {})", set.count);
        static constexpr double f32[] = {4e-7, 8e-7, 1.5e-6};
        static constexpr double f16[] = {4e-4, 6.5e-4, 8.5e-4};
        p.bias = (storage16 ? f16 : f32)[set.count - 2];
    }
    return p;
}

double warpDepth(double viewDepth, double zMin, double zMax) {
    VEIL_CHECK(zMin > 0.0 && zMax > zMin, "moment depth range [{}, {}] must satisfy 0 < min < max",
               zMin, zMax);
    const double zv = std::max(viewDepth, 1e-30);
    return (std::log(zv) - std::log(zMin)) / (std::log(zMax) - std::log(zMin)) * 2.0 - 1.0;
}

DepthRange depthRangeFromSphere(double centreDepth, double radius, double nearPlane) {
    VEIL_CHECK(nearPlane > 0.0 && radius > 0.0, "bounding sphere needs radius > 0 and near > 0");
    DepthRange r;
    r.zMin = std::max(centreDepth - radius, nearPlane);
    r.zMax = std::max(centreDepth + radius, r.zMin * 1.001);
    return r;
}

std::complex<double> trigCircle(double z, double wrappingZone) {
    // [Munstermann18 Eq. 5]
    return std::polar(1.0, (2.0 * std::numbers::pi - wrappingZone) * 0.5 * (z + 1.0));
}

void accumulate(Moments& m, double z, double alpha, double wrappingZone) {
    const double a = -std::log1p(-std::clamp(alpha, 0.0, 1.0 - 1e-7)); // [Munstermann18 sec. 3.1]
    m.b[0] += a;
    if (m.set.basis == MomentBasis::Power) {
        double zk = 1.0;
        for (std::size_t k = 1; k < m.b.size(); ++k)
            m.b[k] += a * (zk *= z);
    } else {
        const std::complex<double> x = trigCircle(z, wrappingZone);
        std::complex<double> xk = 1.0;
        for (std::size_t k = 1; k < m.b.size(); ++k)
            m.b[k] += a * (xk *= x);
    }
}

double exactAbsorbance(const std::vector<Layer>& layers, double zf) {
    double a = 0.0;
    for (const Layer& l : layers)
        if (l.z < zf) a -= std::log1p(-std::clamp(l.alpha, 0.0, 1.0 - 1e-7));
    return a;
}

namespace {

// Solves the Hermitian positive definite system M q = r by an LDL^H decomposition (the
// Cholesky decomposition of [Munstermann18 Algorithms 1 and 2] without square roots).
template <typename T>
T conjT(T v) {
    if constexpr (std::is_same_v<T, double>)
        return v;
    else
        return std::conj(v);
}

template <typename T>
std::vector<T> solveLdl(std::vector<T> M, std::vector<T> r, int n) {
    std::vector<double> D(n);
    auto at = [&](int i, int j) -> T& { return M[static_cast<std::size_t>(i * n + j)]; };
    for (int j = 0; j < n; ++j) {
        double dj = std::real(at(j, j));
        for (int k = 0; k < j; ++k)
            dj -= std::norm(at(j, k)) * D[k];
        D[j] = dj;
        for (int i = j + 1; i < n; ++i) {
            T lij = at(i, j);
            for (int k = 0; k < j; ++k)
                lij -= at(i, k) * conjT(at(j, k)) * D[k];
            at(i, j) = lij / dj;
        }
    }
    for (int i = 0; i < n; ++i) // L y = r
        for (int k = 0; k < i; ++k)
            r[i] -= at(i, k) * r[k];
    for (int i = 0; i < n; ++i)
        r[i] /= D[i];
    for (int i = n - 1; i >= 0; --i) // L^H q = y
        for (int k = i + 1; k < n; ++k)
            r[i] -= conjT(at(k, i)) * r[k];
    return r;
}

// Newton divided differences for the polynomial p with p(x_l) = v_l, expanded into monomial
// coefficients u ([Munstermann18 Algorithms 1 and 2]: "divided differences to solve a Vandermonde
// system").
template <typename T>
std::vector<T> interpolate(const std::vector<T>& x, std::vector<T> c) {
    const std::size_t n = x.size();
    for (std::size_t j = 1; j < n; ++j)
        for (std::size_t i = n - 1; i >= j; --i)
            c[i] = (c[i] - c[i - 1]) / (x[i] - x[i - j]);
    std::vector<T> u(n, T(0));
    u[0] = c[n - 1];
    for (std::size_t i = n - 1; i-- > 0;) {
        // u <- u * (X - x_i) + c_i
        for (std::size_t k = n - 1; k > 0; --k)
            u[k] = u[k - 1] - x[i] * u[k];
        u[0] = -x[i] * u[0] + c[i];
    }
    return u;
}

// [Munstermann18 sec. 5.2]: piecewise linear stand-in for the angle of x on the unit circle.
double psi(std::complex<double> x) {
    const double re = x.real(), im = x.imag();
    if (im >= 0.0) return re >= 0.0 ? -re + im : 2.0 - re - im;
    return re < 0.0 ? 4.0 + re - im : 6.0 + re + im;
}

double powerAbsorbance(const Moments& m, double zf, const MomentParams& p) {
    const int M = m.set.count, n = M / 2 + 1;
    VEIL_CHECK(static_cast<int>(p.biasVector.size()) == M,
               "power-moment bias vector needs {} entries (got {})", M, p.biasVector.size());
    std::vector<double> b(M + 1);
    b[0] = 1.0;
    for (int j = 1; j <= M; ++j)
        b[j] = (1.0 - p.bias) * m.b[j].real() / m.b0() + p.bias * p.biasVector[j - 1];
    // [Munstermann18 Algorithm 1]: Hankel system for the kernel polynomial through z_0 = zf.
    std::vector<double> H(static_cast<std::size_t>(n * n)), rhs(n);
    double zk = 1.0;
    for (int i = 0; i < n; ++i, zk *= zf) {
        rhs[i] = zk;
        for (int k = 0; k < n; ++k)
            H[static_cast<std::size_t>(i * n + k)] = b[i + k];
    }
    const std::vector<double> q = solveLdl(H, rhs, n);
    std::vector<double> nodes{zf};
    if (M == 4) {
        const auto r = solveQuadratic({q[0], q[1], q[2]});
        nodes.insert(nodes.end(), r.begin(), r.end());
    } else if (M == 6) {
        const auto r = solveCubicBlinn({q[0], q[1], q[2], q[3]}, true);
        nodes.insert(nodes.end(), r.begin(), r.end());
    } else {
        const auto r = solveQuarticNeumark({q[0], q[1], q[2], q[3], q[4]}, true);
        nodes.insert(nodes.end(), r.begin(), r.end());
    }
    std::vector<double> v(n);
    v[0] = p.overestimation;
    for (int l = 1; l < n; ++l)
        v[l] = nodes[l] < zf ? 1.0 : 0.0;
    const std::vector<double> u = interpolate(nodes, v);
    double a = 0.0;
    for (int j = 0; j < n; ++j)
        a += b[j] * u[j];
    return a;
}

double trigAbsorbance(const Moments& m, double zf, const MomentParams& p) {
    using C = std::complex<double>;
    const int M = m.set.count, n = M + 1;
    std::vector<C> b(n);
    b[0] = 1.0;
    for (int j = 1; j <= M; ++j)
        b[j] = (1.0 - p.bias) * m.b[j] / m.b0(); // [Munstermann18 sec. 5.3]
    // [Munstermann18 Algorithm 2]: Hermitian Toeplitz system; right-hand side (1, x0, ..., x0^m).
    const C x0 = trigCircle(zf, p.wrappingZone);
    std::vector<C> T(static_cast<std::size_t>(n * n)), rhs(n);
    C xk = 1.0;
    for (int i = 0; i < n; ++i, xk *= x0) {
        rhs[i] = xk;
        for (int k = 0; k < n; ++k)
            T[static_cast<std::size_t>(i * n + k)] = i >= k ? b[i - k] : std::conj(b[k - i]);
    }
    const std::vector<C> q = solveLdl(T, rhs, n);
    // With T = E(b b^H) the kernel polynomial vanishing at the other support points is
    // sum_j conj(q_j) x^j (q = T^-1 b(x0) gives conj(V) q = e_0 / w_0).
    std::vector<C> nodes{x0};
    if (M == 2) {
        const auto r = solveQuadraticComplex({std::conj(q[0]), std::conj(q[1]), std::conj(q[2])});
        nodes.insert(nodes.end(), r.begin(), r.end());
    } else if (M == 3) {
        const auto r = solveCubicComplex(
            {std::conj(q[0]), std::conj(q[1]), std::conj(q[2]), std::conj(q[3])}, true);
        nodes.insert(nodes.end(), r.begin(), r.end());
    } else {
        const auto r = solveQuarticComplex(
            {std::conj(q[0]), std::conj(q[1]), std::conj(q[2]), std::conj(q[3]), std::conj(q[4])},
            true);
        nodes.insert(nodes.end(), r.begin(), r.end());
    }
    // [Munstermann18 Eq. 6] with the wrapping zone.
    const double psi0 = psi(x0), psiEnd = psi(trigCircle(1.0, p.wrappingZone));
    std::vector<C> v(n);
    v[0] = p.overestimation;
    for (int l = 1; l < n; ++l) {
        const double s = psi(nodes[l]);
        v[l] = s < psi0 ? 1.0 : s <= psiEnd ? 0.0 : (s - psiEnd) / (7.0 - psiEnd);
    }
    const std::vector<C> u = interpolate(nodes, v);
    C a = 0.0;
    for (int j = 0; j < n; ++j)
        a += b[j] * u[j];
    return a.real();
}

} // namespace

double absorbance(const Moments& m, double zf, const MomentParams& p) {
    const double b0 = m.b0();
    if (!(b0 > 1e-12)) return 0.0; // [Munstermann18 sec. 3.2]: no opacity, early return
    double a =
        m.set.basis == MomentBasis::Power ? powerAbsorbance(m, zf, p) : trigAbsorbance(m, zf, p);
    // The normalized absorbance is a CDF value in [0, 1]; a failed solve falls back to the
    // overestimation weight (docs/oit.md#moment-constants: NaN fallback of a public port).
    if (!std::isfinite(a)) a = p.overestimation;
    return b0 * std::clamp(a, 0.0, 1.0);
}

std::array<double, 4> quantizePower4(const std::array<double, 4>& b) {
    const double s3 = std::sqrt(3.0);
    return {1.5 * b[0] - 2.0 * b[2] + 0.5, 0.5 * s3 * b[0] - 2.0 * s3 / 9.0 * b[2] + 0.5,
            4.0 * b[1] - 4.0 * b[3], 0.5 * b[1] + 0.5 * b[3]};
}

std::array<double, 4> dequantizePower4(const std::array<double, 4>& q) {
    // Inverses of the two 2x2 blocks above.
    const double s3 = std::sqrt(3.0);
    const double o0 = q[0] - 0.5, o1 = q[1] - 0.5;
    const double detOdd = 1.5 * (-2.0 * s3 / 9.0) - (-2.0) * (0.5 * s3);
    const double b1 = ((-2.0 * s3 / 9.0) * o0 + 2.0 * o1) / detOdd;
    const double b3 = (-(0.5 * s3) * o0 + 1.5 * o1) / detOdd;
    const double detEven = 4.0 * 0.5 - (-4.0) * 0.5;
    const double b2 = (0.5 * q[2] + 4.0 * q[3]) / detEven;
    const double b4 = (-0.5 * q[2] + 4.0 * q[3]) / detEven;
    return {b1, b2, b3, b4};
}

namespace {

// docs/oit.md#moment-constants, "16-bit quantization transforms for 6 and 8 power moments"
// (row-major).
constexpr double kQ6Odd[9] = {2.5,   -1.87499864450, 1.26583039016,
                              -10.0, 4.20757543111,  -1.47644882902,
                              8.0,   -1.83257678661, 0.71061660238};
constexpr double kQ6Even[9] = {4.0,           9.0, -0.57759806484, -4.0,          -24.0,
                               4.61936647543, 0.0, 16.0,           -3.07953906655};
constexpr double kQ6OddInv[9] = {-0.02877789192, 0.09995235706, 0.25893353755,
                                 0.47635550422,  0.84532580931, 0.90779616657,
                                 1.55242808973,  1.05472570761, 0.83327335647};
constexpr double kQ6EvenInv[9] = {0.00001253044, -0.24998746956, -0.37498825271,
                                  0.16668494186, 0.16668494186,  0.21876713299,
                                  0.86602540579, 0.86602540579,  0.81189881793};
constexpr double kQ6OddOffset[3] = {0.5, 0.5, 0.5};
constexpr double kQ6EvenOffset[3] = {0.0, 0.0, 0.018888946};
constexpr double kQ8Odd[16] = {
    3.48044635732474,  -27.5760737514826,  55.1267384344761,   -31.5311110403183,
    1.26797185782836,  -0.928755808743913, -2.07520453231032,  1.23598848322588,
    -2.1671560004294,  6.17950199592966,   -0.276515571579297, -4.23583042392097,
    0.974332879165755, -0.443426830933027, -0.360491648368785, 0.310149466050223};
constexpr double kQ8Even[16] = {
    0.280504133158527, -0.757633844606942, 0.392179589334688,  -0.887531871812237,
    -2.01362265883247, 0.221551373038988,  -1.06107954265125,  2.83887201588367,
    -7.31010494985321, 13.9855979699139,   -0.114305766176437, -7.4361899359832,
    -15.8954215629556, 79.6186327084103,   -127.457278992502,  63.7349456687829};
constexpr double kQ8OddInv[16] = {
    -0.00482399708502382, -0.423201508674231, 0.0348312382605129, 1.67179208266592,
    -0.0233402218644408,  -0.832829097046478, 0.0193406040499625, 1.21021509068975,
    -0.010888537031885,   -0.926393772997063, -0.11723394414779,  0.983723301818275,
    -0.0308713357806732,  -0.937989172670245, -0.218033377677099, 0.845991731322996};
constexpr double kQ8EvenInv[16] = {
    -0.976220278891035, -0.456139260269401, -0.0504335521016742, 0.000838800390651085,
    -1.04828341778299,  -0.229726640510149, 0.0259608334616091,  -0.00133632693205861,
    -1.03115268628604,  -0.077844420809897, 0.00443408851014257, -0.0103744938457406,
    -0.996038443434636, 0.0175438624416783, -0.0361414253243963, -0.00317839994022725};
constexpr double kQ8OddOffset[4] = {0.5, 0.5, 0.5, 0.5};
constexpr double kQ8EvenOffset[4] = {0.972481993925964, 1.0, 0.999179192513328, 0.991778293073131};

// out = v M (rowVector) or M v, for an n x n row-major M.
void multiply(const double* M, const double* v, double* out, int n, bool rowVector) {
    for (int j = 0; j < n; ++j) {
        double s = 0.0;
        for (int k = 0; k < n; ++k)
            s += rowVector ? v[k] * M[k * n + j] : M[j * n + k] * v[k];
        out[j] = s;
    }
}

struct PowerQuantization {
    const double *oddQ, *evenQ, *oddInv, *evenInv, *oddOffset, *evenOffset;
    bool rowVector;
};

PowerQuantization powerQuantization(std::size_t count) {
    if (count == 6)
        return {kQ6Odd, kQ6Even, kQ6OddInv, kQ6EvenInv, kQ6OddOffset, kQ6EvenOffset, true};
    VEIL_CHECK(count == 8, "16-bit power-moment storage needs 4, 6 or 8 moments (got {})", count);
    return {kQ8Odd, kQ8Even, kQ8OddInv, kQ8EvenInv, kQ8OddOffset, kQ8EvenOffset, false};
}

} // namespace

std::vector<double> quantizePower(const std::vector<double>& n) {
    if (n.size() == 4) {
        const auto q = quantizePower4({n[0], n[1], n[2], n[3]});
        return {q.begin(), q.end()};
    }
    const PowerQuantization t = powerQuantization(n.size());
    const int h = static_cast<int>(n.size() / 2);
    std::vector<double> odd(h), even(h), q(n.size());
    for (int i = 0; i < h; ++i)
        odd[i] = n[2 * i], even[i] = n[2 * i + 1];
    multiply(t.oddQ, odd.data(), q.data(), h, t.rowVector);
    multiply(t.evenQ, even.data(), q.data() + h, h, t.rowVector);
    for (int i = 0; i < h; ++i)
        q[i] += t.oddOffset[i], q[h + i] += t.evenOffset[i];
    return q;
}

std::vector<double> dequantizePower(const std::vector<double>& q) {
    if (q.size() == 4) {
        const auto n = dequantizePower4({q[0], q[1], q[2], q[3]});
        return {n.begin(), n.end()};
    }
    const PowerQuantization t = powerQuantization(q.size());
    const int h = static_cast<int>(q.size() / 2);
    std::vector<double> odd(h), even(h), oddN(h), evenN(h), n(q.size());
    for (int i = 0; i < h; ++i)
        odd[i] = q[i] - t.oddOffset[i], even[i] = q[h + i] - t.evenOffset[i];
    multiply(t.oddInv, odd.data(), oddN.data(), h, t.rowVector);
    multiply(t.evenInv, even.data(), evenN.data(), h, t.rowVector);
    for (int i = 0; i < h; ++i)
        n[2 * i] = oddN[i], n[2 * i + 1] = evenN[i];
    return n;
}

} // namespace veil::oit::cpu
