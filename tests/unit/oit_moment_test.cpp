// CPU reference of moment-based OIT [Munstermann18] against things it did not produce: known roots,
// exact transmittance of layer stacks, the structural properties of a transmittance (range,
// monotonicity), and the quantization transform's inverse.
#include "base/error.h"
#include "oit/cpu/moment_solvers.h"
#include "oit/cpu/moments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace veil::oit::cpu {

namespace {

const MomentSet kSets[] = {{MomentBasis::Power, 4},
                           {MomentBasis::Power, 6},
                           {MomentBasis::Power, 8},
                           {MomentBasis::Trigonometric, 3},
                           {MomentBasis::Trigonometric, 4}};

Moments build(MomentSet set, const std::vector<Layer>& layers, const MomentParams& p) {
    Moments m(set);
    for (const Layer& l : layers)
        accumulate(m, l.z, l.alpha, p.wrappingZone);
    return m;
}

template <std::size_t N>
std::vector<double> polyFromRoots(const std::array<double, N>& r) {
    std::vector<double> c{1.0};
    for (double x : r) {
        std::vector<double> n(c.size() + 1, 0.0);
        for (std::size_t i = 0; i < c.size(); ++i)
            n[i + 1] += c[i], n[i] -= x * c[i];
        c = n;
    }
    return c;
}

template <std::size_t N, typename T>
void expectRoots(std::array<double, N> want, std::array<T, N> got, double tol, const char* what) {
    std::sort(want.begin(), want.end());
    std::sort(got.begin(), got.end());
    for (std::size_t i = 0; i < N; ++i)
        EXPECT_NEAR(got[i], want[i], tol) << what << " root " << i;
}

// Round to IEEE binary16 (11 significant bits, round to nearest even), normal range: b_0 is
// stored in RGBA16F (shaders/oit/moment/storage16.glsl).
double toHalf(double v) {
    if (v == 0.0) return 0.0;
    int e = 0;
    std::frexp(v, &e);
    const double ulp = std::ldexp(1.0, e - 11);
    return std::nearbyint(v / ulp) * ulp;
}
double unorm16(double v) { return std::round(std::clamp(v, 0.0, 1.0) * 65535.0) / 65535.0; }

// The 16-bit accumulation of storage16.glsl, done here from docs/oit.md#moment-constants and
// [Munstermann18 sec. 4.1] (not from the shader): per fragment, b_0 += -ln(1 - alpha) and is stored
// in half precision, and the normalized power moments n = b_1..4 / b_0 are rebuilt as (n_old b0_old
// + b_new) / (b0_old + b0_new) and stored through the quantization transform in UNORM16.
Moments accumulate16Power4(const std::vector<Layer>& layers, double wrappingZone) {
    double b0 = 0.0;
    std::array<double, 4> q = quantizePower4({0, 0, 0, 0});
    for (int j = 0; j < 4; ++j)
        q[j] = unorm16(q[j]);
    for (const Layer& l : layers) {
        Moments one({MomentBasis::Power, 4});
        accumulate(one, l.z, l.alpha, wrappingZone);
        // The sum is divided by in full precision; only the stored b_0 is rounded to half.
        const double nb0 = b0 + one.b0();
        std::array<double, 4> n = dequantizePower4(q);
        for (int j = 0; j < 4; ++j)
            n[j] = ((b0 > 0.0 ? n[j] * b0 : 0.0) + one.b[j + 1].real()) / nb0;
        q = quantizePower4(n);
        for (int j = 0; j < 4; ++j)
            q[j] = unorm16(q[j]);
        b0 = toHalf(nb0);
    }
    Moments m({MomentBasis::Power, 4});
    m.b[0] = b0;
    const std::array<double, 4> n = dequantizePower4(q);
    for (int j = 0; j < 4; ++j)
        m.b[j + 1] = n[j] * b0;
    return m;
}

// A valid normalized power-moment vector n_k = E(z^k), k = 1..count, of a random distribution
// on [-1, 1] with 1..6 points; every third one pushes points toward +-1 (the range's corners).
std::vector<double> randomNormalizedPowerMoments(std::mt19937& rng, int count) {
    std::uniform_real_distribution<double> uz(-1.0, 1.0), uw(0.0, 1.0);
    std::uniform_int_distribution<int> points(1, 6);
    const int k = points(rng);
    const bool edge = uw(rng) < 0.3;
    std::vector<double> n(count, 0.0);
    double total = 0.0;
    std::vector<double> z(k), w(k);
    for (int i = 0; i < k; ++i) {
        z[i] = uz(rng);
        if (edge) z[i] = std::copysign(std::min(1.0, 3.0 * std::abs(z[i])), z[i]);
        w[i] = uw(rng) + 1e-9;
        total += w[i];
    }
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < count; ++j)
            n[j] += w[i] / total * std::pow(z[i], j + 1);
    return n;
}

// Half a UNORM16 step in every stored value, carried through the inverse transform (affine):
// component j of the dequantized moments moves by at most sum_i |Q^-1_ji| h / 2, h = 1/65535
// (Q^-1 read off dequantizePower at the unit vectors).
std::vector<double> unorm16StepBound(int count) {
    std::vector<double> bound(count, 0.0);
    const std::vector<double> origin = dequantizePower(std::vector<double>(count, 0.0));
    for (int i = 0; i < count; ++i) {
        std::vector<double> e(count, 0.0);
        e[i] = 1.0;
        const std::vector<double> col = dequantizePower(e);
        for (int j = 0; j < count; ++j)
            bound[j] += std::abs(col[j] - origin[j]) * 0.5 / 65535.0;
    }
    return bound;
}

// Emulations of the two 16-bit storages of the GPU, written from [Munstermann18 sec. 4.1] and
// docs/oit.md#moment-constants (not from the shaders), for power moments:
//   quantized (storage16.glsl): per fragment n = (n_old b0_old + b_new) / (b0_old + b0_new),
//     stored through quantizePower in UNORM16, b_0 in half;
//   half (emit.glsl into RGBA16F): every unnormalized moment and b_0 a half float, each
//     fragment's value rounded to half and the sum rounded again (blending at the target's
//     precision).
enum class Storage16 { Quantized, Half };
Moments accumulate16(const MomentSet& set, const std::vector<Layer>& layers, Storage16 storage,
                     double wrappingZone) {
    const int m = set.count;
    Moments out(set);
    if (storage == Storage16::Half) {
        for (const Layer& l : layers) {
            Moments one(set);
            accumulate(one, l.z, l.alpha, wrappingZone);
            for (int k = 0; k <= m; ++k)
                out.b[k] = {toHalf(out.b[k].real() + toHalf(one.b[k].real())),
                            toHalf(out.b[k].imag() + toHalf(one.b[k].imag()))};
        }
        return out;
    }
    if (set.basis == MomentBasis::Trigonometric) { // SNORM16 normalized moments, no transform
        auto snorm16 = [](double v) {
            return std::round(std::clamp(v, -1.0, 1.0) * 32767.0) / 32767.0;
        };
        double b0 = 0.0;
        std::vector<std::complex<double>> n(m + 1);
        for (const Layer& l : layers) {
            Moments one(set);
            accumulate(one, l.z, l.alpha, wrappingZone);
            const double nb0 = b0 + one.b0();
            for (int j = 1; j <= m; ++j) {
                const std::complex<double> v = (n[j] * b0 + one.b[j]) / nb0;
                n[j] = {snorm16(v.real()), snorm16(v.imag())};
            }
            b0 = toHalf(nb0);
        }
        out.b[0] = b0;
        for (int j = 1; j <= m; ++j)
            out.b[j] = n[j] * b0;
        return out;
    }
    double b0 = 0.0;
    std::vector<double> q = quantizePower(std::vector<double>(m, 0.0));
    for (double& v : q)
        v = unorm16(v);
    for (const Layer& l : layers) {
        Moments one(set);
        accumulate(one, l.z, l.alpha, wrappingZone);
        const double nb0 = b0 + one.b0();
        std::vector<double> n = dequantizePower(q);
        for (int j = 0; j < m; ++j)
            n[j] = ((b0 > 0.0 ? n[j] * b0 : 0.0) + one.b[j + 1].real()) / nb0;
        q = quantizePower(n);
        for (double& v : q)
            v = unorm16(v);
        b0 = toHalf(nb0);
    }
    out.b[0] = b0;
    const std::vector<double> n = dequantizePower(q);
    for (int j = 0; j < m; ++j)
        out.b[j + 1] = n[j] * b0;
    return out;
}

} // namespace

TEST(OitMomentSolvers, QuadraticCubicQuarticKnownRoots) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const double scale = 0.1 + 3.0 * std::abs(u(rng)); // leading coefficient
        std::array<double, 2> r2{u(rng), u(rng)};
        auto c2 = polyFromRoots(r2);
        const auto g2 = solveQuadratic({scale * c2[0], scale * c2[1], scale * c2[2]});
        expectRoots(r2, g2, 1e-6, "quadratic");

        std::array<double, 3> r3{u(rng), u(rng), u(rng)};
        auto c3 = polyFromRoots(r3);
        for (auto& v : c3)
            v *= scale;
        expectRoots(r3, solveCubicBlinn({c3[0], c3[1], c3[2], c3[3]}), 2e-5, "Blinn (raw)");
        expectRoots(r3, solveCubicBlinn({c3[0], c3[1], c3[2], c3[3]}, true), 1e-6, "Blinn");

        std::array<double, 4> r4{u(rng), u(rng), u(rng), u(rng)};
        auto c4 = polyFromRoots(r4);
        for (auto& v : c4)
            v *= scale;
        expectRoots(r4, solveQuarticNeumark({c4[0], c4[1], c4[2], c4[3], c4[4]}, true), 1e-5,
                    "Neumark");
    }
    // Separated roots: the closed forms alone are accurate, no polishing.
    const auto c3 = polyFromRoots(std::array<double, 3>{-0.9, 0.1, 0.7});
    expectRoots(std::array<double, 3>{-0.9, 0.1, 0.7},
                solveCubicBlinn({c3[0], c3[1], c3[2], c3[3]}), 1e-12, "Blinn separated");
    const auto c4 = polyFromRoots(std::array<double, 4>{-0.8, -0.3, 0.2, 0.9});
    expectRoots(std::array<double, 4>{-0.8, -0.3, 0.2, 0.9},
                solveQuarticNeumark({c4[0], c4[1], c4[2], c4[3], c4[4]}), 1e-10,
                "Neumark separated");
    // Zero and double roots stay finite.
    for (double r : solveCubicBlinn({0, 0, 1, 1}))
        EXPECT_TRUE(std::isfinite(r));
    for (double r : solveQuarticNeumark({0.0625, 0, -0.5, 0, 1}))
        EXPECT_NEAR(std::abs(r), 0.5, 1e-6);
}

TEST(OitMomentSolvers, ComplexRootsOnTheUnitCircle) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 2.0 * std::numbers::pi);
    for (int trial = 0; trial < 200; ++trial) {
        std::array<Complex, 4> r;
        for (auto& x : r)
            x = std::polar(1.0, u(rng));
        const Complex lead = std::polar(0.5 + trial * 0.01, u(rng));
        auto poly = [&](int n) {
            std::vector<Complex> c{lead};
            for (int k = 0; k < n; ++k) {
                std::vector<Complex> next(c.size() + 1, 0.0);
                for (std::size_t i = 0; i < c.size(); ++i)
                    next[i + 1] += c[i], next[i] -= r[k] * c[i];
                c = next;
            }
            return c;
        };
        auto matched = [&](auto got, int n, double tol) {
            for (int k = 0; k < n; ++k) {
                double best = 1e9;
                for (const Complex& g : got)
                    best = std::min(best, std::abs(g - r[k]));
                EXPECT_LT(best, tol) << "degree " << n << " root " << k;
            }
        };
        const auto c3 = poly(3);
        matched(solveCubicComplex({c3[0], c3[1], c3[2], c3[3]}, true), 3, 1e-5);
        const auto c4 = poly(4);
        matched(solveQuarticComplex({c4[0], c4[1], c4[2], c4[3], c4[4]}, true), 4, 1e-4);
    }
}

TEST(OitMomentReference, DepthWarpAndSphere) {
    EXPECT_NEAR(warpDepth(0.5, 0.5, 8.0), -1.0, 1e-15);
    EXPECT_NEAR(warpDepth(8.0, 0.5, 8.0), 1.0, 1e-15);
    EXPECT_NEAR(warpDepth(2.0, 0.5, 8.0), 0.0, 1e-15); // geometric mean -> 0 (log warp)
    const DepthRange r = depthRangeFromSphere(10.0, 3.0, 0.1);
    EXPECT_DOUBLE_EQ(r.zMin, 7.0);
    EXPECT_DOUBLE_EQ(r.zMax, 13.0);
    EXPECT_DOUBLE_EQ(depthRangeFromSphere(1.0, 3.0, 0.1).zMin, 0.1);
    EXPECT_THROW(warpDepth(1.0, 0.0, 1.0), veil::Error);
    EXPECT_THROW(defaultMomentParams({MomentBasis::Power, 5}), veil::Error);
}

// [Munstermann18 sec. 4.1 / 5.1]: with k <= m/2 surfaces (power) or k <= m (trigonometric) the
// moment vector lies on the boundary of the moment space and the representation is unique, so the
// reconstruction is exact at depths between surfaces; at a surface's own depth it includes
// beta times that surface's absorbance (the overestimation). The bias breaks exactness: we
// assert it with a negligible bias (1e-9) and, with the paper's float32 biases, a looser bound.
TEST(OitMomentReference, ExactForFewSurfaces) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uz(-0.9, 0.9), ua(0.1, 0.8);
    for (const MomentSet set : kSets) {
        const int maxLayers = set.basis == MomentBasis::Power ? set.count / 2 : set.count;
        double worstTiny = 0.0, worstPaper = 0.0, worstSelf = 0.0;
        for (int trial = 0; trial < 40; ++trial) {
            const int k = 1 + trial % maxLayers;
            std::vector<Layer> layers;
            for (int i = 0; i < k; ++i)
                layers.push_back({uz(rng), ua(rng)});
            std::sort(layers.begin(), layers.end(), [](auto a, auto b) { return a.z < b.z; });
            bool separated = true;
            for (int i = 1; i < k; ++i)
                separated &= layers[i].z - layers[i - 1].z > 0.1;
            if (!separated) continue;
            MomentParams tiny = defaultMomentParams(set);
            tiny.bias = 1e-9;
            const MomentParams paper = defaultMomentParams(set);
            const Moments m = build(set, layers, tiny);
            std::vector<double> probes{-0.99, 0.99};
            for (int i = 0; i + 1 < k; ++i)
                probes.push_back(0.5 * (layers[i].z + layers[i + 1].z));
            for (double zf : probes) {
                const double exact = std::exp(-exactAbsorbance(layers, zf));
                worstTiny = std::max(worstTiny, std::abs(transmittanceAt(m, zf, tiny) - exact));
                worstPaper = std::max(worstPaper, std::abs(transmittanceAt(m, zf, paper) - exact));
            }
            for (const Layer& l : layers) { // overestimation at the surface itself
                const double want =
                    exactAbsorbance(layers, l.z) - tiny.overestimation * std::log1p(-l.alpha);
                worstSelf = std::max(worstSelf, std::abs(absorbance(m, l.z, tiny) - want));
            }
        }
        EXPECT_LT(worstTiny, 1e-3) << set.name();
        EXPECT_LT(worstSelf, 1e-3) << set.name();
        // [Munstermann18 Fig. 3]: the float32 biases visibly degrade power moments, more with more
        // moments.
        const double paperBound = set.basis == MomentBasis::Trigonometric ? 5e-3
                                  : set.count == 4                        ? 1e-2
                                  : set.count == 6                        ? 5e-2
                                                                          : 0.15;
        EXPECT_LT(worstPaper, paperBound) << set.name();
        std::printf("[ moments ] %s exact-case max |T - T_exact|: bias 1e-9 %.2e, paper bias "
                    "%.2e; at-surface beta error %.2e\n",
                    set.name().c_str(), worstTiny, worstPaper, worstSelf);
    }
}

TEST(OitMomentReference, RangeAndMonotoneOnRandomStacks) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uz(-1.0, 1.0), ua(0.0, 0.95);
    for (const MomentSet set : kSets) {
        const MomentParams p = defaultMomentParams(set);
        double worstRise = 0.0;
        for (int trial = 0; trial < 60; ++trial) {
            std::vector<Layer> layers(1 + trial % 20);
            for (auto& l : layers)
                l = {uz(rng), ua(rng)};
            const Moments m = build(set, layers, p);
            double prev = 1.0;
            for (int i = 0; i <= 200; ++i) {
                const double zf = -1.0 + 2.0 * i / 200.0;
                const double t = transmittanceAt(m, zf, p);
                ASSERT_TRUE(std::isfinite(t)) << set.name();
                ASSERT_GE(t, std::exp(-m.b0()) - 1e-12) << set.name();
                ASSERT_LE(t, 1.0) << set.name();
                if (t - prev > 1e-3 && getenv("MOMENT_DEBUG"))
                    std::printf("rise %g at zf %g, %zu layers\n", t - prev, zf, layers.size());
                worstRise = std::max(worstRise, t - prev);
                prev = t;
            }
        }
        // Power moments: (1 - beta) lower + beta upper bound, both monotone: asserted to
        // rounding. Algorithm 2 gives no proper bounds [Munstermann18 sec. 5.1] and its wrapping
        // zone (section 5.2) lets surfaces near z = 1 leak into depths near z = -1, so T may rise a
        // little; measured up to ~0.085 on these stacks, asserted below 0.1.
        EXPECT_LT(worstRise, set.basis == MomentBasis::Power ? 1e-9 : 0.1) << set.name();
        std::printf("[ moments ] %s largest increase of T over depth: %.2e\n", set.name().c_str(),
                    worstRise);
    }
}

TEST(OitMomentReference, NoNanForOneSurfaceAndCoincidentDepths) {
    for (const MomentSet set : kSets) {
        const MomentParams p = defaultMomentParams(set);
        const std::vector<std::vector<Layer>> cases = {
            {{0.3, 0.5}},
            {{0.3, 1.0}},
            {{-1.0, 0.5}},
            {{1.0, 0.5}},
            {{0.3, 1e-6}},
            {{0.3, 0.5}, {0.3, 0.5}},
            {{0.3, 0.5}, {0.3 + 1e-7, 0.7}, {0.3 - 1e-7, 0.2}},
            {{0.3, 0.9}, {0.3, 0.9}, {0.3, 0.9}, {0.3, 0.9}, {0.3, 0.9}, {0.3, 0.9}},
        };
        for (const auto& layers : cases) {
            const Moments m = build(set, layers, p);
            for (double zf : {-1.0, 0.0, 0.3 - 1e-7, 0.3, 0.3 + 1e-7, 0.5, 1.0}) {
                const double t = transmittanceAt(m, zf, p);
                ASSERT_TRUE(std::isfinite(t)) << set.name() << " zf " << zf;
                EXPECT_GE(t, 0.0);
                EXPECT_LE(t, 1.0);
            }
            // One surface: nothing in front of it, the whole absorbance behind it.
            if (layers.size() == 1 && layers[0].z < 0.9 && layers[0].alpha > 0.01 &&
                layers[0].alpha < 0.99) {
                EXPECT_NEAR(transmittanceAt(m, std::min(layers[0].z + 0.3, 1.0), p),
                            std::exp(-m.b0()), 0.02)
                    << set.name();
                if (layers[0].z > -0.7) {
                    EXPECT_NEAR(transmittanceAt(m, layers[0].z - 0.3, p), 1.0, 0.02) << set.name();
                }
            }
        }
    }
}

TEST(OitMomentReference, Power4QuantizationRoundTrip) {
    // docs/oit.md#moment-constants: q = b Q + offset maps valid normalized moment vectors into [0,
    // 1]^4; stored in UNORM16 each q_i is off by at most h / 2, h = 1 / 65535. The transform is
    // affine, so the moments come back off by at most sum_i |Q^-1_ji| h / 2 in component j
    // (Q^-1 read off dequantizePower4 at the unit vectors).
    std::array<double, 4> bound{};
    const std::array<double, 4> origin = dequantizePower4({0, 0, 0, 0});
    for (int i = 0; i < 4; ++i) {
        std::array<double, 4> e{};
        e[i] = 1.0;
        const std::array<double, 4> col = dequantizePower4(e);
        for (int j = 0; j < 4; ++j)
            bound[j] += std::abs(col[j] - origin[j]) * 0.5 / 65535.0;
    }
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> uz(-1.0, 1.0), uw(0.0, 1.0);
    double worst = 0.0;
    for (int trial = 0; trial < 2000; ++trial) {
        // A valid normalized moment vector: moments of a random 3-point distribution.
        std::array<double, 4> b{};
        double total = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double z = uz(rng), w = uw(rng);
            total += w;
            for (int j = 0; j < 4; ++j)
                b[j] += w * std::pow(z, j + 1);
        }
        for (double& v : b)
            v /= total;
        const auto q = quantizePower4(b);
        std::array<double, 4> q16;
        for (int j = 0; j < 4; ++j) {
            EXPECT_GE(q[j], -1e-12);
            EXPECT_LE(q[j], 1.0 + 1e-12);
            q16[j] = unorm16(q[j]);
        }
        const auto exact = dequantizePower4(q);
        const auto back = dequantizePower4(q16);
        for (int j = 0; j < 4; ++j) {
            EXPECT_NEAR(exact[j], b[j], 1e-12);
            EXPECT_LE(std::abs(back[j] - b[j]), bound[j] * (1.0 + 1e-9)) << "moment " << j + 1;
            worst = std::max(worst, std::abs(back[j] - b[j]) / bound[j]);
        }
    }
    std::printf("[ moments ] 16-bit round trip: worst error %.3f of the half-step bound "
                "(%.3g, %.3g, %.3g, %.3g)\n",
                worst, bound[0], bound[1], bound[2], bound[3]);
    EXPECT_GT(worst, 0.25); // the bound is not vacuous
}

TEST(OitMomentReference, Storage16ReconstructionWithinMomentBounds) {
    // [Munstermann18 sec. 3.2]: for given (biased) moments the true absorbance lies between the
    // lower bound L (overestimation beta = 0) and the upper bound U (beta = 1); the reconstruction
    // is (1 - beta) L + beta U, so the method's own error is up to max(beta, 1 - beta)(U - L).
    // The 16-bit path (half b_0, UNORM16 normalized moments rewritten per fragment) with the
    // 16-bit bias (6e-5 toward (0, 0.628, 0, 0.628)) must reconstruct inside the bounds that
    // the exact double moments give under that same bias, widened by what quantization can
    // move: the normalized moments by at most the half step through Q^-1 per fragment (see
    // Power4QuantizationRoundTrip; each rewrite scales the earlier error by b0_old / b0_new
    // <= 1), so they lie in the box exact +- n_layers * step, and [L, U] is taken over the
    // box's 16 corners; b_0 is off by up to 2^-11 relative per fragment (absorbance scales
    // with b_0): n_layers 2^-11 b_0, plus 1e-3.
    // The stronger bias itself moves the reconstruction away from float32's: [Munstermann18
    // sec. 4.1] and docs/oit.md#moment-constants accept that (blur of close surfaces); printed, not
    // bounded.
    const MomentSet set{MomentBasis::Power, 4};
    const MomentParams p32 = defaultMomentParams(set, false), p16 = defaultMomentParams(set, true);
    std::array<double, 4> step{}; // half a UNORM16 step through Q^-1, per normalized moment
    const std::array<double, 4> origin = dequantizePower4({0, 0, 0, 0});
    for (int i = 0; i < 4; ++i) {
        std::array<double, 4> e{};
        e[i] = 1.0;
        const std::array<double, 4> col = dequantizePower4(e);
        for (int j = 0; j < 4; ++j)
            step[j] += std::abs(col[j] - origin[j]) * 0.5 / 65535.0;
    }
    MomentParams lower = p16, upper = p16;
    lower.overestimation = 0.0;
    upper.overestimation = 1.0;
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> uz(-1.0, 1.0), ua(0.05, 0.9);
    double worstOut = -1.0, worstQuant = 0.0, worstBias = 0.0;
    int checks = 0;
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<Layer> layers(1 + trial % 8);
        for (auto& l : layers)
            l = {uz(rng), ua(rng)};
        const Moments exact = build(set, layers, p32);
        const Moments m16 = accumulate16Power4(layers, p16.wrappingZone);
        const double slack = 1e-3 + exact.b0() * layers.size() * std::ldexp(1.0, -11);
        for (int i = 0; i <= 40; ++i) {
            const double zf = -1.0 + 2.0 * i / 40.0;
            double lo = absorbance(exact, zf, lower), hi = absorbance(exact, zf, upper);
            for (int corner = 0; corner < 16; ++corner) {
                Moments moved = exact;
                for (int j = 0; j < 4; ++j)
                    moved.b[j + 1] += (corner >> j & 1 ? 1.0 : -1.0) * double(layers.size()) *
                                      step[j] * exact.b0();
                lo = std::min(lo, absorbance(moved, zf, lower));
                hi = std::max(hi, absorbance(moved, zf, upper));
            }
            const double a16 = absorbance(m16, zf, p16);
            EXPECT_GE(a16, lo - slack) << layers.size() << " layers, zf " << zf;
            EXPECT_LE(a16, hi + slack) << layers.size() << " layers, zf " << zf;
            worstOut = std::max({worstOut, (lo - a16) / slack, (a16 - hi) / slack});
            worstQuant = std::max(worstQuant, std::abs(a16 - absorbance(exact, zf, p16)));
            worstBias = std::max(worstBias,
                                 std::abs(absorbance(exact, zf, p16) - absorbance(exact, zf, p32)));
            ++checks;
        }
    }
    std::printf("[ moments ] 16-bit power 4: %d checks; max |A(quantized) - A(exact moments)| "
                "%.2e, worst excursion outside [L, U] %.2f of the slack; the 16-bit bias moves A "
                "by up to %.3f from float32\n",
                checks, worstQuant, worstOut, worstBias);
}

TEST(OitMomentReference, TrigonometricNormalizedMomentsFitSnorm16) {
    // [Munstermann18 sec. 5.3]: the 16-bit path stores b_k / b_0 directly in SNORM16
    // (storage16.glsl, no transform), which holds [-1, 1]: each normalized trigonometric moment is
    // a convex combination of points on the unit circle, so its real and imaginary parts must fit.
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> uz(-1.0, 1.0), ua(0.05, 0.9);
    const MomentSet set{MomentBasis::Trigonometric, 4};
    const MomentParams p = defaultMomentParams(set, true);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Layer> layers(1 + trial % 6);
        for (auto& l : layers)
            l = {uz(rng), ua(rng)};
        const Moments m = build(set, layers, p);
        for (int k = 1; k <= set.count; ++k) {
            const std::complex<double> n = m.b[k] / m.b0();
            ASSERT_LE(std::abs(n), 1.0 + 1e-12) << "moment " << k;
        }
    }
}

TEST(OitMomentReference, Power6And8QuantizationRoundTrip) {
    // docs/oit.md#moment-constants transforms for 6 and 8 power moments (and 4, through the same
    // entry): (1) valid normalized moment vectors land in [0, 1]^m (this is what decides where the
    // offsets go: added before the transform they map valid vectors to [-0.25, 1.3] for 6 and
    // [-1.9, 0.74] for 8 moments); (2) the published inverse undoes the transform to the
    // precision it is printed with (11 digits for 6 moments: |Q Q^-1 - I| <= 7e-11, times
    // |q| <= 1 and 3 terms: 1e-9); (3) stored in UNORM16, the moments come back within the
    // half-step bound of unorm16StepBound.
    for (int count : {4, 6, 8}) {
        const std::vector<double> bound = unorm16StepBound(count);
        std::mt19937 rng(11 + count);
        double worst = 0.0, lo = 1.0, hi = 0.0;
        for (int trial = 0; trial < 4000; ++trial) {
            const std::vector<double> n = randomNormalizedPowerMoments(rng, count);
            const std::vector<double> q = quantizePower(n);
            ASSERT_EQ(q.size(), std::size_t(count));
            std::vector<double> q16(count);
            for (int j = 0; j < count; ++j) {
                lo = std::min(lo, q[j]);
                hi = std::max(hi, q[j]);
                EXPECT_GE(q[j], -1e-9) << count << " moments, value " << j;
                EXPECT_LE(q[j], 1.0 + 1e-9) << count << " moments, value " << j;
                q16[j] = unorm16(q[j]);
            }
            const std::vector<double> exact = dequantizePower(q), back = dequantizePower(q16);
            for (int j = 0; j < count; ++j) {
                EXPECT_NEAR(exact[j], n[j], 1e-9) << count << " moments, moment " << j + 1;
                // The clamp of unorm16() may move a value at the range's edge by 1e-9 more.
                EXPECT_LE(std::abs(back[j] - n[j]), bound[j] * (1.0 + 1e-6) + 1e-8)
                    << count << " moments, moment " << j + 1;
                worst = std::max(worst, std::abs(back[j] - n[j]) / bound[j]);
            }
        }
        std::printf("[ moments ] %d power moments, 16-bit: stored range [%.2e, %.6f], worst round "
                    "trip %.3f of the half-step bound (moment 1: %.3g)\n",
                    count, lo, hi, worst, bound[0]);
        EXPECT_GT(worst, 0.25) << count; // the bound is not vacuous
    }
}

TEST(OitMomentReference, Storage16ErrorWithinFloat32OnRandomStacks) {
    // The 16-bit storages must not be worse than 1.5x the float32 variant against
    // the exact transmittance. Per stack (1..12 layers, some pairs 1e-3 apart in warped depth),
    // the transmittance in front of every layer is compared with the exact one: float32 =
    // exact double moments with the float32 bias (the GPU float32 path rounds far less than
    // the bias), quantized and half = the emulations above with their own default biases
    // (the technique's: 16-bit column of docs/oit.md#moment-constants, half x kHalfBiasFactor,
    // which this test passes in). The mean absolute error of each storage over all layers must be
    // at most 1.5x float32's, plus 2e-3 for the quantization noise itself (UNORM16 through Q^-1 and
    // half b_0, measured well below).
    constexpr double kHalfBiasFactor = 1.0; // src/oit/moment/moment.cpp
    for (const MomentSet& set : kSets) {
        const int count = set.count;
        const MomentParams p32 = defaultMomentParams(set, false);
        const MomentParams pq = defaultMomentParams(set, true);
        MomentParams ph = pq;
        ph.bias *= kHalfBiasFactor;
        std::mt19937 rng(40 + count + (set.basis == MomentBasis::Power ? 0 : 10));
        std::uniform_real_distribution<double> uz(-0.95, 0.95), ua(0.05, 0.9), u(0.0, 1.0);
        double e32 = 0.0, eq = 0.0, eh = 0.0;
        int samples = 0;
        bool finite = true;
        for (int trial = 0; trial < 400; ++trial) {
            std::vector<Layer> layers(1 + trial % 12);
            for (std::size_t i = 0; i < layers.size(); ++i) {
                layers[i] = {uz(rng), ua(rng)};
                if (i > 0 && u(rng) < 0.2) layers[i].z = layers[i - 1].z + 1e-3;
            }
            const Moments exact = build(set, layers, p32);
            const Moments mq = accumulate16(set, layers, Storage16::Quantized, p32.wrappingZone);
            const Moments mh = accumulate16(set, layers, Storage16::Half, p32.wrappingZone);
            for (const Layer& l : layers) {
                const double t = std::exp(-exactAbsorbance(layers, l.z));
                const double a32 = transmittanceAt(exact, l.z, p32);
                const double aq = transmittanceAt(mq, l.z, pq), ah = transmittanceAt(mh, l.z, ph);
                finite = finite && std::isfinite(aq) && std::isfinite(ah);
                e32 += std::abs(a32 - t);
                eq += std::abs(aq - t);
                eh += std::abs(ah - t);
                ++samples;
            }
        }
        e32 /= samples, eq /= samples, eh /= samples;
        std::printf("[ moments ] %s mean |T - T_exact|: float32 %.4f, quantized 16-bit %.4f "
                    "(%.2fx), half %.4f (%.2fx)\n",
                    set.name().c_str(), e32, eq, eq / e32, eh, eh / e32);
        EXPECT_TRUE(finite) << set.name();
        EXPECT_LE(eq, 1.5 * e32 + 2e-3) << set.name() << ", quantized";
        EXPECT_LE(eh, 1.5 * e32 + 2e-3) << set.name() << ", half";
    }
}

} // namespace veil::oit::cpu
