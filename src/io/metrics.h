// Image metrics for `veil compare` and `veil regress`: error measures on linear
// HDR RGB(A) float images, SSIM on display-encoded images, and a per-pixel statistical test
// of a stochastic estimator against a reference (the approach of Mitsuba 3's
// src/render/tests/test_renders.py: test the estimator, do not threshold one noisy image).
//
// Conventions shared by every function here:
//  - Only the RGB channels are compared (alpha, when present, is ignored).
//  - The two images must have the same width and height (veil::Error otherwise).
//  - Sums are in double precision.
#pragma once

#include "base/image.h"

#include <array>
#include <string>
#include <vector>

namespace veil::metrics {

// sqrt(mean over RGB of (a - b)^2).
double rmse(const ImageF& a, const ImageF& b);
// max over RGB of |a - b|; NaN when a value of either image is NaN.
double maxAbs(const ImageF& a, const ImageF& b);
// RMSE / mean(b): the RMSE relative to the reference's mean RGB value (0 when both are 0,
// +inf when only the reference is all zero).
double normalizedRmse(const ImageF& a, const ImageF& reference);
// Relative MSE, mean over RGB of (a - b)^2 / (b^2 + eps) with b the reference ([Rousselle11], as
// Mitsuba reports it). eps keeps dark pixels from dominating.
constexpr double kRelMseEpsilon = 1e-2;
double relativeMse(const ImageF& a, const ImageF& reference, double eps = kRelMseEpsilon);
// The p-th percentile (0 < p <= 100) of |a - b| over all RGB values, nearest-rank definition:
// the value at rank ceil(p / 100 * n) of the n sorted errors. p = 99 ignores the worst 1%
// (fireflies, silhouette pixels) that max-abs reports.
double percentileAbsError(const ImageF& a, const ImageF& b, double p = 99.0);
// The largest RGB value of an image (the peak of psnr()).
double peak(const ImageF& reference);
// 10 log10(peak^2 / MSE) dB with peak = the largest RGB value of the reference: +inf when
// MSE = 0, NaN when the reference is all zero and MSE > 0.
double psnr(const ImageF& a, const ImageF& reference);

// Mean structural similarity ([Wang04], Eq. 13 with the
// paper's 11 x 11 circular-symmetric Gaussian window of sigma 1.5, K1 = 0.01, K2 = 0.03 and
// dynamic range L = 1) on images already display-encoded in [0, 1] (use toneMapSrgb first for
// HDR radiance). Local statistics are Gaussian-weighted; near the border the window is cut to
// the image and its weights renormalized, so every pixel has a value. The result is the mean
// over all pixels and the three channels.
constexpr double kSsimK1 = 0.01, kSsimK2 = 0.03;
constexpr int kSsimWindow = 11;
constexpr double kSsimSigma = 1.5;
double ssim(const ImageF& a, const ImageF& b);

// HDR radiance to display values: x * exposure, then the ACES fit of [Narkowicz16] (aces)
// or a clamp to [0, 1], then the sRGB transfer function (IEC 61966-2-1). RGB out.
enum class ToneMap { Clamp, Aces };
// The sRGB transfer function (IEC 61966-2-1) of a linear value clamped to [0, 1].
float srgbEncode(double linear);
ImageF toneMapSrgb(const ImageF& hdr, double exposure = 1.0, ToneMap op = ToneMap::Clamp);

// A heat map of the error: per pixel e = max over RGB of |a - b|, mapped through a
// black - blue - red - yellow - white ramp with e = scale at white (values above clamp).
// RGB in [0, 1], for a PNG. scale <= 0 (or not finite) means the image's own largest finite
// error; NaN and infinite errors are white.
ImageF heatMap(const ImageF& a, const ImageF& b, double scale = 0.0);
// The heat map's ramp: RGB at e / scale = 0, 1/4, 1/2, 3/4, 1, linear in between (the colour
// bar of the regress report is drawn from it).
const std::array<std::array<float, 3>, 5>& heatMapStops();

// The metrics by name, as `veil compare --metric` and regression suites spell them.
// "higher is better" holds for psnr and ssim: their thresholds are lower bounds.
const std::vector<std::string>& metricNames(); // rmse, maxabs, relmse, p99, psnr, ssim, nrmse
bool isMetricName(const std::string& name);
bool higherIsBetter(const std::string& name);
// Computes one metric on linear images; ssim tone-maps both with `op` and `exposure` first.
// Every metric is NaN when a value of either image is NaN (no threshold passes NaN).
double compute(const std::string& name, const ImageF& image, const ImageF& reference,
               double exposure = 1.0, ToneMap op = ToneMap::Clamp);
// Whether `value` passes threshold `t` for metric `name` (NaN never passes).
bool withinThreshold(const std::string& name, double value, double t);

// Per-pixel mean and unbiased variance of n renders of the same frame (n >= 1; variance 0
// for n = 1), RGB.
struct PixelStats {
    ImageF mean, variance;
    int count = 0;
};
PixelStats pixelStats(const std::vector<ImageF>& samples);

enum class Correction { Bonferroni, Holm };
struct PixelTestOptions {
    double alpha = 0.01; // family-wise significance level over all tested values
    Correction correction = Correction::Holm;
    // A floor on the standard error of the difference, so that values with no sample
    // variance (deterministic pixels) are not rejected for storage rounding: relative to the
    // larger |mean| (RGBA16F targets round to 2^-11 relative) plus an absolute term.
    double relativeFloor = 0x1p-11;
    double absoluteFloor = 1e-6;
};
struct PixelTestResult {
    int pixels = 0;         // pixels tested
    int tests = 0;          // values tested (3 per pixel)
    int rejectedPixels = 0; // pixels with at least one rejected channel
    int rejectedValues = 0; // channels rejected
    double fraction = 0.0;  // rejectedPixels / pixels
    double minP = 1.0;      // smallest p-value seen
    ImageF rejected;        // 1 channel: 1 where the pixel was rejected
};
// Welch's unequal-variance t test per pixel and channel of H0: E[a] = E[b], from the samples'
// means and variances (a reference of one deterministic image: count 1, variance 0, which
// makes it a one-sample t test with n_a - 1 degrees of freedom). p-values are two-sided from
// Student's t with the Welch-Satterthwaite degrees of freedom (the normal distribution when
// the floor alone makes the standard error). The family of 3 x pixels tests is held at
// `alpha` by Bonferroni (p <= alpha / m) or Holm's step-down (p_(k) <= alpha / (m - k + 1)).
PixelTestResult welchPixelTest(const PixelStats& a, const PixelStats& b,
                               const PixelTestOptions& options = {});

// Two-sided p-value of Student's t with `df` degrees of freedom (df = inf: normal).
double studentTwoSidedP(double t, double df);

} // namespace veil::metrics
