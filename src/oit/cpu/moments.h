// CPU double-precision reference of moment-based order-independent transparency
// [Munstermann18]. No GL. Used by the unit tests and by the
// GL tests, which feed it the same fragments the GPU saw.
//
//   warpDepth           [Munstermann18 sec. 3.3]: logarithmic depth in [zMin, zMax] -> [-1, 1]
//   accumulate          [Munstermann18 sec. 3.1]: b = sum_l -ln(1 - alpha_l) * b(z_l); b_0 =
//   absorbance trigonometric b(z)  [Munstermann18 Eq. 5]: x(z) = exp((2 pi - theta) i (z + 1) / 2),
//   theta = wrapping
//                       zone angle (Eq. 3 is theta = 0)
//   absorbance          [Munstermann18 Algorithm 1] (power moments, Hankel) / Algorithm 2
//   (trigonometric,
//                       Toeplitz), on b / b_0 biased as in docs/oit.md#moment-constants, times b_0
//   quantizePower4      16-bit storage transform of the normalized 4 power moments
//   quantizePower       the same for 4, 6 or 8 power moments (docs/oit.md#moment-constants)
//
// Biasing: power moments are interpolated toward a bias vector, b' = (1 - a) b + a b*;
// trigonometric moments b_1..b_m are multiplied by (1 - a) [Munstermann18 sec. 5.3].
#pragma once

#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

namespace veil::oit::cpu {

enum class MomentBasis { Power, Trigonometric };

struct MomentSet {
    MomentBasis basis = MomentBasis::Power;
    int count = 4;            // m: power 4, 6, 8 (even); trigonometric 2, 3, 4
    std::string name() const; // "p4", "t3", ...
};

struct MomentParams {
    double overestimation = 0.25; // beta, [Munstermann18 sec. 3.2]
    double bias = 5e-7;           // alpha of the biasing (docs/oit.md#moment-constants)
    // power moments: b*_1..b*_m (the target of the interpolation); unused for trigonometric.
    std::vector<double> biasVector;
    double wrappingZone = 0.31415926535897932; // theta = pi / 10, [Munstermann18 sec. 5.2]
};

// The paper's / docs/oit.md#moment-constants defaults for the set and storage (float32 or 16 bit).
MomentParams defaultMomentParams(MomentSet set, bool storage16 = false);

// [Munstermann18 sec. 3.3]: z = (ln zv - ln zMin) / (ln zMax - ln zMin) * 2 - 1 (not clamped).
double warpDepth(double viewDepth, double zMin, double zMax);

struct DepthRange {
    double zMin = 0.1, zMax = 100.0;
};
// [Munstermann18 sec. 3.3]: depth range of a bounding sphere whose centre lies at view depth
// `centreDepth`, with zMin kept above the near plane.
DepthRange depthRangeFromSphere(double centreDepth, double radius, double nearPlane);

// Moments b_0..b_m. Power: real parts only. Trigonometric: b_j = E(x^j).
struct Moments {
    MomentSet set;
    std::vector<std::complex<double>> b; // size m + 1
    explicit Moments(MomentSet s) : set(s), b(static_cast<std::size_t>(s.count) + 1) {}
    double b0() const { return b[0].real(); }
};

// Point on the unit circle for warped depth z [Munstermann18 Eq. 5].
std::complex<double> trigCircle(double z, double wrappingZone);

// Adds one surface at warped depth z with coverage alpha (clamped to [0, 1 - 1e-7] so the
// absorbance stays finite).
void accumulate(Moments& moments, double z, double alpha, double wrappingZone);

// A(z_f, b, beta) of [Munstermann18 secs. 3.2, 4 and 5]: the reconstructed absorbance in front of
// warped depth zf, in [0, b_0]. Never NaN: a failed reconstruction falls back to beta * b_0.
double absorbance(const Moments& moments, double zf, const MomentParams& params);
inline double transmittanceAt(const Moments& m, double zf, const MomentParams& p) {
    return std::exp(-absorbance(m, zf, p));
}

// Exact absorbance in front of zf (surfaces at depth < zf) for a list of (z, alpha).
struct Layer {
    double z = 0.0;
    double alpha = 0.0;
};
double exactAbsorbance(const std::vector<Layer>& layers, double zf);

// 16-bit storage of 4 normalized power moments b_k / b_0 (docs/oit.md#moment-constants): odd pair
// (b1, b3) by [[1.5, -2], [sqrt(3)/2, -2 sqrt(3)/9]] + 0.5, even pair (b2, b4) by
// [[4, -4], [0.5, 0.5]] (rows); valid moment vectors land in [0, 1]^4. Returns (q1, q2, q3, q4)
// = (odd0, odd1, even0, even1).
std::array<double, 4> quantizePower4(const std::array<double, 4>& normalized);
std::array<double, 4> dequantizePower4(const std::array<double, 4>& quantized);

// 16-bit storage of m = 4, 6 or 8 normalized power moments n_k = b_k / b_0, k = 1..m
// ([Munstermann18 sec. 4.1], transforms of docs/oit.md#moment-constants): odd (n_1, n_3, ...) and
// even (n_2, n_4,
// ...) moments are transformed separately and offset so that valid moment vectors land in
// [0, 1]^m; the result is (odd transformed..., even transformed...). m = 4 is quantizePower4;
// m = 6 applies the transform as a row vector times the matrix (n Q + offset), m = 8 as the
// matrix times a column vector (Q n + offset). The notes' "offsets before quantizing" for 6 and
// 8 moments would map valid vectors far outside [0, 1] (tests/unit/oit_moment_test.cpp checks
// the range): the offsets are added after the transform and subtracted before its inverse.
std::vector<double> quantizePower(const std::vector<double>& normalized);
std::vector<double> dequantizePower(const std::vector<double>& quantized);

} // namespace veil::oit::cpu
