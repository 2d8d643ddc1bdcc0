#include "io/metrics.h"

#include "base/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace veil::metrics {

namespace {

void checkSameSize(const ImageF& a, const ImageF& b) {
    VEIL_CHECK(a.width == b.width && a.height == b.height,
               "cannot compare a {}x{} image with a {}x{} one", a.width, a.height, b.width,
               b.height);
    VEIL_CHECK(a.channels >= 3 && b.channels >= 3,
               "cannot compare images of {} and {} channels: RGB or RGBA needed", a.channels,
               b.channels);
    VEIL_CHECK(a.width > 0 && a.height > 0, "cannot compare empty images");
}

// Calls f(a_value, b_value) for every RGB value.
template <class F>
void forEachRgb(const ImageF& a, const ImageF& b, F&& f) {
    const std::size_t n = static_cast<std::size_t>(a.width) * a.height;
    for (std::size_t p = 0; p < n; ++p)
        for (int c = 0; c < 3; ++c)
            f(double(a.pixels[p * a.channels + c]), double(b.pixels[p * b.channels + c]));
}

double count(const ImageF& a) { return 3.0 * a.width * a.height; }

double mse(const ImageF& a, const ImageF& b) {
    double sum = 0.0;
    forEachRgb(a, b, [&](double x, double y) { sum += (x - y) * (x - y); });
    return sum / count(a);
}

// [Narkowicz16] (the same fit as shaders/frame/tonemap).
double acesFit(double x) {
    return std::clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// Continued fraction of the regularized incomplete beta function (Abramowitz and Stegun
// 26.5.8), evaluated by the modified Lentz method.
double betaContinuedFraction(double a, double b, double x) {
    const double tiny = 1e-300;
    double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
    if (std::abs(d) < tiny) d = tiny;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m <= 500; ++m) {
        // The even step d_{2m} = m (b - m) x / ((a + 2m - 1)(a + 2m)) ...
        double num = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
        d = 1.0 + num * d;
        c = 1.0 + num / c;
        d = 1.0 / (std::abs(d) < tiny ? tiny : d);
        c = std::abs(c) < tiny ? tiny : c;
        h *= d * c;
        // ... and the odd step d_{2m+1} = -(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)).
        num = -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
        d = 1.0 + num * d;
        c = 1.0 + num / c;
        d = 1.0 / (std::abs(d) < tiny ? tiny : d);
        c = std::abs(c) < tiny ? tiny : c;
        const double step = d * c;
        h *= step;
        if (std::abs(step - 1.0) < 1e-15) break;
    }
    return h;
}

// I_x(a, b).
double regularizedIncompleteBeta(double a, double b, double x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    const double logFront =
        a * std::log(x) + b * std::log1p(-x) + std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b);
    // The fraction converges fast for x < (a + 1) / (a + b + 2); use the symmetry
    // I_x(a, b) = 1 - I_{1-x}(b, a) beyond.
    if (x < (a + 1.0) / (a + b + 2.0))
        return std::exp(logFront) * betaContinuedFraction(a, b, x) / a;
    return 1.0 - std::exp(logFront) * betaContinuedFraction(b, a, 1.0 - x) / b;
}

} // namespace

double rmse(const ImageF& a, const ImageF& b) {
    checkSameSize(a, b);
    return std::sqrt(mse(a, b));
}

double maxAbs(const ImageF& a, const ImageF& b) {
    checkSameSize(a, b);
    // std::max(m, NaN) keeps m: a NaN pixel must make the maximum NaN, not vanish.
    double m = 0.0;
    bool nan = false;
    forEachRgb(a, b, [&](double x, double y) {
        const double d = std::abs(x - y);
        nan = nan || std::isnan(d);
        m = std::max(m, d);
    });
    return nan ? std::numeric_limits<double>::quiet_NaN() : m;
}

double normalizedRmse(const ImageF& a, const ImageF& reference) {
    checkSameSize(a, reference);
    double sum = 0.0;
    forEachRgb(a, reference, [&](double, double y) { sum += y; });
    const double e = std::sqrt(mse(a, reference)), mean = sum / count(a);
    if (e == 0.0) return 0.0;
    return mean > 0.0 ? e / mean : std::numeric_limits<double>::infinity();
}

double relativeMse(const ImageF& a, const ImageF& reference, double eps) {
    checkSameSize(a, reference);
    VEIL_CHECK(eps > 0.0, "relative MSE needs eps > 0 (got {})", eps);
    double sum = 0.0;
    forEachRgb(a, reference, [&](double x, double y) { sum += (x - y) * (x - y) / (y * y + eps); });
    return sum / count(a);
}

double percentileAbsError(const ImageF& a, const ImageF& b, double p) {
    checkSameSize(a, b);
    VEIL_CHECK(p > 0.0 && p <= 100.0, "percentile {} not in (0, 100]", p);
    std::vector<double> e;
    e.reserve(static_cast<std::size_t>(count(a)));
    bool nan = false;
    forEachRgb(a, b, [&](double x, double y) {
        e.push_back(std::abs(x - y));
        nan = nan || std::isnan(e.back());
    });
    // NaN has no rank (nth_element needs a strict weak order).
    if (nan) return std::numeric_limits<double>::quiet_NaN();
    const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * double(e.size())));
    const std::size_t k = std::clamp<std::size_t>(rank, 1, e.size()) - 1;
    std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(k), e.end());
    return e[k];
}

double peak(const ImageF& reference) {
    VEIL_CHECK(reference.channels >= 3, "no RGB in an image of {} channels", reference.channels);
    double p = 0.0;
    bool nan = false;
    forEachRgb(reference, reference, [&](double, double y) {
        nan = nan || std::isnan(y);
        p = std::max(p, y);
    });
    return nan ? std::numeric_limits<double>::quiet_NaN() : p;
}

double psnr(const ImageF& a, const ImageF& reference) {
    checkSameSize(a, reference);
    const double top = peak(reference);
    const double m = mse(a, reference);
    if (m == 0.0) return std::numeric_limits<double>::infinity();
    return top > 0.0 ? 10.0 * std::log10(top * top / m) : std::numeric_limits<double>::quiet_NaN();
}

double ssim(const ImageF& a, const ImageF& b) {
    checkSameSize(a, b);
    const int w = a.width, h = a.height, r = kSsimWindow / 2;
    std::array<double, kSsimWindow> g{};
    for (int i = 0; i < kSsimWindow; ++i)
        g[i] = std::exp(-double((i - r) * (i - r)) / (2.0 * kSsimSigma * kSsimSigma));
    const double c1 = (kSsimK1 * 1.0) * (kSsimK1 * 1.0), c2 = (kSsimK2 * 1.0) * (kSsimK2 * 1.0);
    // The Gaussian is separable: blur x, a, b, a^2, b^2 and ab along rows, then columns.
    const std::size_t n = static_cast<std::size_t>(w) * h;
    std::vector<std::array<double, 6>> rows(n), cols(n);
    double total = 0.0;
    for (int c = 0; c < 3; ++c) {
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::array<double, 6> s{};
                for (int i = -r; i <= r; ++i) {
                    const int xi = x + i;
                    if (xi < 0 || xi >= w) continue;
                    const double wt = g[i + r], va = a.at(xi, y, c), vb = b.at(xi, y, c);
                    s[0] += wt, s[1] += wt * va, s[2] += wt * vb;
                    s[3] += wt * va * va, s[4] += wt * vb * vb, s[5] += wt * va * vb;
                }
                rows[static_cast<std::size_t>(y) * w + x] = s;
            }
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::array<double, 6> s{};
                for (int j = -r; j <= r; ++j) {
                    const int yj = y + j;
                    if (yj < 0 || yj >= h) continue;
                    const auto& row = rows[static_cast<std::size_t>(yj) * w + x];
                    for (int k = 0; k < 6; ++k)
                        s[k] += g[j + r] * row[k];
                }
                cols[static_cast<std::size_t>(y) * w + x] = s;
            }
        for (const auto& s : cols) {
            const double ma = s[1] / s[0], mb = s[2] / s[0];
            // Clamped at 0: the weighted second moments minus the squared means can come out
            // a rounding error below 0 for flat windows.
            const double va = std::max(0.0, s[3] / s[0] - ma * ma);
            const double vb = std::max(0.0, s[4] / s[0] - mb * mb);
            const double cov = s[5] / s[0] - ma * mb;
            total += ((2.0 * ma * mb + c1) * (2.0 * cov + c2)) /
                     ((ma * ma + mb * mb + c1) * (va + vb + c2));
        }
    }
    return total / (3.0 * double(n));
}

float srgbEncode(double c) {
    c = std::clamp(c, 0.0, 1.0);
    return static_cast<float>(c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055);
}

ImageF toneMapSrgb(const ImageF& hdr, double exposure, ToneMap op) {
    VEIL_CHECK(hdr.channels >= 3, "cannot tone map an image of {} channels", hdr.channels);
    ImageF out(hdr.width, hdr.height, 3);
    for (int y = 0; y < hdr.height; ++y)
        for (int x = 0; x < hdr.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const double v = double(hdr.at(x, y, c)) * exposure;
                out.at(x, y, c) = srgbEncode(op == ToneMap::Aces ? acesFit(v) : v);
            }
    return out;
}

const std::array<std::array<float, 3>, 5>& heatMapStops() {
    static constexpr std::array<std::array<float, 3>, 5> kStops{
        {{0, 0, 0}, {0.1f, 0.1f, 0.8f}, {0.85f, 0.1f, 0.1f}, {1, 0.85f, 0}, {1, 1, 1}}};
    return kStops;
}

ImageF heatMap(const ImageF& a, const ImageF& b, double scale) {
    checkSameSize(a, b);
    ImageF e(a.width, a.height, 1);
    double largest = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            double m = 0.0;
            for (int c = 0; c < 3; ++c)
                m = std::max(m, std::abs(double(a.at(x, y, c)) - double(b.at(x, y, c))));
            // A NaN channel makes the pixel NaN (std::max would drop it); NaN and inf
            // errors are drawn white, and the automatic scale is the largest finite error.
            for (int c = 0; c < 3; ++c)
                if (std::isnan(a.at(x, y, c)) || std::isnan(b.at(x, y, c)))
                    m = std::numeric_limits<double>::infinity();
            e.at(x, y, 0) = static_cast<float>(m);
            if (std::isfinite(m)) largest = std::max(largest, m);
        }
    if (!std::isfinite(scale) || scale <= 0.0) scale = largest > 0.0 ? largest : 1.0;
    const auto& kStops = heatMapStops();
    ImageF out(a.width, a.height, 3);
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const double t = std::clamp(double(e.at(x, y, 0)) / scale, 0.0, 1.0) * 4.0;
            const int i = std::min(3, static_cast<int>(t));
            const double f = t - i;
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) =
                    static_cast<float>(kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c]));
        }
    return out;
}

const std::vector<std::string>& metricNames() {
    static const std::vector<std::string> names{"rmse", "maxabs", "relmse", "p99",
                                                "psnr", "ssim",   "nrmse"};
    return names;
}

bool isMetricName(const std::string& name) {
    const auto& n = metricNames();
    return std::find(n.begin(), n.end(), name) != n.end();
}

bool higherIsBetter(const std::string& name) { return name == "psnr" || name == "ssim"; }

double compute(const std::string& name, const ImageF& image, const ImageF& reference,
               double exposure, ToneMap op) {
    // A NaN pixel in either image makes every metric NaN, which no threshold passes: no
    // metric may hide it (std::max drops NaN, nrmse would call it +inf, ssim clamps it).
    checkSameSize(image, reference);
    bool nan = false;
    forEachRgb(image, reference,
               [&](double x, double y) { nan = nan || std::isnan(x) || std::isnan(y); });
    if (nan && isMetricName(name)) return std::numeric_limits<double>::quiet_NaN();
    if (name == "rmse") return rmse(image, reference);
    if (name == "maxabs") return maxAbs(image, reference);
    if (name == "relmse") return relativeMse(image, reference);
    if (name == "p99") return percentileAbsError(image, reference, 99.0);
    if (name == "psnr") return psnr(image, reference);
    if (name == "nrmse") return normalizedRmse(image, reference);
    if (name == "ssim")
        return ssim(toneMapSrgb(image, exposure, op), toneMapSrgb(reference, exposure, op));
    throw Error(fmt::format("unknown metric '{}'", name));
}

bool withinThreshold(const std::string& name, double value, double t) {
    if (std::isnan(value)) return false;
    return higherIsBetter(name) ? value >= t : value <= t;
}

PixelStats pixelStats(const std::vector<ImageF>& samples) {
    VEIL_CHECK(!samples.empty(), "pixel statistics need at least one image");
    for (const ImageF& s : samples)
        checkSameSize(s, samples.front());
    const ImageF& f = samples.front();
    PixelStats st{ImageF(f.width, f.height, 3), ImageF(f.width, f.height, 3),
                  static_cast<int>(samples.size())};
    const double n = double(samples.size());
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                for (const ImageF& s : samples)
                    sum += s.at(x, y, c);
                const double mean = sum / n;
                double sq = 0.0; // two passes: no cancellation for large means
                for (const ImageF& s : samples)
                    sq += (s.at(x, y, c) - mean) * (s.at(x, y, c) - mean);
                st.mean.at(x, y, c) = static_cast<float>(mean);
                st.variance.at(x, y, c) = static_cast<float>(n > 1 ? sq / (n - 1.0) : 0.0);
            }
    return st;
}

double studentTwoSidedP(double t, double df) {
    if (std::isnan(t)) return std::numeric_limits<double>::quiet_NaN();
    if (std::isinf(df)) return std::erfc(std::abs(t) / std::sqrt(2.0));
    VEIL_CHECK(df > 0.0, "Student's t needs df > 0 (got {})", df);
    // P(|T| > |t|) = I_{df / (df + t^2)}(df / 2, 1 / 2).
    return regularizedIncompleteBeta(0.5 * df, 0.5, df / (df + t * t));
}

PixelTestResult welchPixelTest(const PixelStats& a, const PixelStats& b,
                               const PixelTestOptions& o) {
    checkSameSize(a.mean, b.mean);
    VEIL_CHECK(a.count >= 2 || b.count >= 2,
               "the per-pixel test needs at least 2 renders on one side (got {} and {})", a.count,
               b.count);
    VEIL_CHECK(o.alpha > 0.0 && o.alpha < 1.0, "significance level {} not in (0, 1)", o.alpha);
    const int w = a.mean.width, h = a.mean.height;
    std::vector<double> p(static_cast<std::size_t>(w) * h * 3);
    PixelTestResult r;
    r.pixels = w * h;
    r.tests = static_cast<int>(p.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double ma = a.mean.at(x, y, c), mb = b.mean.at(x, y, c);
                const double ea = a.variance.at(x, y, c) / a.count;
                const double eb = b.variance.at(x, y, c) / b.count;
                // Welch-Satterthwaite degrees of freedom of the sample part of se^2.
                double den = 0.0;
                if (a.count > 1) den += ea * ea / (a.count - 1);
                if (b.count > 1) den += eb * eb / (b.count - 1);
                const double sample = ea + eb;
                const double fl =
                    o.relativeFloor * std::max(std::abs(ma), std::abs(mb)) + o.absoluteFloor;
                const double se = std::sqrt(sample + fl * fl);
                const double df = sample > 0.0 && den > 0.0
                                      ? sample * sample / den
                                      : std::numeric_limits<double>::infinity();
                const double pv = studentTwoSidedP((ma - mb) / se, df);
                p[(static_cast<std::size_t>(y) * w + x) * 3 + c] = pv;
                r.minP = std::min(r.minP, pv);
            }
    // Holm: reject the k-th smallest p-value (k from 1) while p_(k) <= alpha / (m - k + 1);
    // the first that is not rejected stops it. Bonferroni: every p <= alpha / m.
    const double m = double(p.size());
    std::vector<char> reject(p.size(), 0);
    if (o.correction == Correction::Bonferroni) {
        for (std::size_t i = 0; i < p.size(); ++i)
            reject[i] = !(p[i] > o.alpha / m); // NaN rejects
    } else {
        std::vector<std::size_t> order(p.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
            const double pi = std::isnan(p[i]) ? -1.0 : p[i], pj = std::isnan(p[j]) ? -1.0 : p[j];
            return pi < pj;
        });
        for (std::size_t k = 0; k < order.size(); ++k) {
            const double pv = p[order[k]];
            if (!std::isnan(pv) && pv > o.alpha / (m - double(k))) break;
            reject[order[k]] = 1;
        }
    }
    r.rejected = ImageF(w, h, 1);
    for (int i = 0; i < w * h; ++i) {
        const int k = reject[3 * i] + reject[3 * i + 1] + reject[3 * i + 2];
        r.rejectedValues += k;
        r.rejectedPixels += k > 0;
        r.rejected.pixels[static_cast<std::size_t>(i)] = k > 0 ? 1.0f : 0.0f;
    }
    r.fraction = double(r.rejectedPixels) / double(r.pixels);
    return r;
}

} // namespace veil::metrics
