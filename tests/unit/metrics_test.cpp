// src/io/metrics.h against values computed by hand from the definitions.
#include "base/error.h"
#include "io/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace veil::test {

namespace {

ImageF filled(int w, int h, float v, int channels = 3) {
    ImageF img(w, h, channels);
    std::fill(img.pixels.begin(), img.pixels.end(), v);
    return img;
}

// A 2 x 1 RGB image from six values.
ImageF pair(std::initializer_list<float> v) {
    ImageF img(2, 1, 3);
    std::copy(v.begin(), v.end(), img.pixels.begin());
    return img;
}

// A deterministic pattern in [0, 1] with structure at several scales.
ImageF pattern(int w, int h) {
    ImageF img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                img.at(x, y, c) = static_cast<float>(0.5 + 0.4 * std::sin(0.37 * x + 1.3 * c) *
                                                               std::cos(0.23 * y - 0.7 * c));
    return img;
}

} // namespace

TEST(MetricsTest, ErrorsOfKnownArrays) {
    // Differences 0.1, -0.2, 0, 0.3, 0, -0.4 over six values.
    const ImageF a = pair({0.1f, 0.0f, 1.0f, 0.8f, 0.5f, 0.2f});
    const ImageF b = pair({0.0f, 0.2f, 1.0f, 0.5f, 0.5f, 0.6f});
    const double mse = (0.01 + 0.04 + 0.09 + 0.16) / 6.0;
    EXPECT_NEAR(metrics::rmse(a, b), std::sqrt(mse), 1e-7);
    EXPECT_NEAR(metrics::maxAbs(a, b), 0.4, 1e-7);
    const double rel = (0.01 / (0.0 + 0.01) + 0.04 / (0.04 + 0.01) + 0.0 + 0.09 / (0.25 + 0.01) +
                        0.0 + 0.16 / (0.36 + 0.01)) /
                       6.0;
    EXPECT_NEAR(metrics::relativeMse(a, b), rel, 1e-6);
    // Peak = the reference's largest value, 1.
    EXPECT_NEAR(metrics::psnr(a, b), 10.0 * std::log10(1.0 / mse), 1e-5);
    EXPECT_NEAR(metrics::normalizedRmse(a, b), std::sqrt(mse) / (2.8 / 6.0), 1e-6);
    // Sorted |errors| 0, 0, 0.1, 0.2, 0.3, 0.4: nearest rank ceil(p/100 * 6).
    EXPECT_NEAR(metrics::percentileAbsError(a, b, 50.0), 0.1, 1e-7);  // rank 3
    EXPECT_NEAR(metrics::percentileAbsError(a, b, 51.0), 0.2, 1e-7);  // rank 4
    EXPECT_NEAR(metrics::percentileAbsError(a, b, 99.0), 0.4, 1e-7);  // rank 6
    EXPECT_NEAR(metrics::percentileAbsError(a, b, 100.0), 0.4, 1e-7); // rank 6
    EXPECT_NEAR(metrics::percentileAbsError(a, b, 10.0), 0.0, 1e-7);  // rank 1
}

TEST(MetricsTest, AlphaIsIgnoredAndSizesMustMatch) {
    ImageF a = filled(3, 2, 0.5f, 4), b = filled(3, 2, 0.5f, 4);
    for (std::size_t i = 3; i < a.pixels.size(); i += 4)
        a.pixels[i] = 0.0f;
    EXPECT_EQ(metrics::rmse(a, b), 0.0);
    EXPECT_EQ(metrics::psnr(a, b), std::numeric_limits<double>::infinity());
    EXPECT_THROW(metrics::rmse(a, filled(2, 3, 0.5f)), Error);
    EXPECT_THROW(metrics::ssim(filled(2, 2, 0.5f, 1), filled(2, 2, 0.5f, 1)), Error);
}

TEST(MetricsTest, PercentileIgnoresAFewFireflies) {
    ImageF a = filled(10, 10, 0.5f), b = filled(10, 10, 0.5f);
    for (int i = 0; i < 300; ++i)
        a.pixels[i] += 0.01f;
    a.at(3, 3, 1) = 100.0f; // one firefly in 300 values
    EXPECT_NEAR(metrics::percentileAbsError(a, b, 99.0), 0.01, 1e-6);
    EXPECT_NEAR(metrics::maxAbs(a, b), 99.5, 1e-4);
}

TEST(MetricsTest, SsimOfAnImageWithItselfIsOne) {
    const ImageF a = pattern(40, 30);
    EXPECT_NEAR(metrics::ssim(a, a), 1.0, 1e-12);
}

TEST(MetricsTest, SsimOfConstantImagesMatchesTheFormula) {
    // No variance anywhere: SSIM = (2 mu_a mu_b + C1) C2 / ((mu_a^2 + mu_b^2 + C1) C2) per
    // pixel ([Wang04], Eq. 13), with C1 = (0.01 L)^2, L = 1.
    const double ma = 0.6, mb = 0.4, c1 = 1e-4;
    const double expected = (2 * ma * mb + c1) / (ma * ma + mb * mb + c1);
    EXPECT_NEAR(metrics::ssim(filled(20, 20, float(ma)), filled(20, 20, float(mb))), expected,
                1e-6);
}

TEST(MetricsTest, SsimOfAConstantOffsetMatchesTheFormula) {
    // b = a + d leaves variances and covariance equal (sigma_a^2 = sigma_b^2 = sigma_ab), so
    // the contrast-structure term is exactly 1 and only the luminance term remains:
    // SSIM = (2 mu (mu + d) + C1) / (mu^2 + (mu + d)^2 + C1). With a checkerboard
    // a = 0.5 +- 0.05 the Gaussian-weighted local mean is 0.5 (the alternating sum of an
    // 11-tap sigma-1.5 Gaussian is ~1e-5 of its sum) except in windows cut by the border,
    // where the mean moves by up to ~0.02 and the luminance term (slope ~0.18 in mu) by
    // ~0.004 on a few border rows: averaged over 80 x 80 pixels, well under 5e-4.
    const int n = 80;
    ImageF a(n, n, 3), b(n, n, 3);
    const double d = 0.2;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c) {
                a.at(x, y, c) = ((x + y) % 2 ? 0.45f : 0.55f);
                b.at(x, y, c) = a.at(x, y, c) + float(d);
            }
    const double mu = 0.5, c1 = 1e-4;
    const double expected = (2 * mu * (mu + d) + c1) / (mu * mu + (mu + d) * (mu + d) + c1);
    EXPECT_NEAR(metrics::ssim(a, b), expected, 5e-4);
    EXPECT_LT(metrics::ssim(a, b), 1.0 - 0.05);
}

TEST(MetricsTest, SsimSeesStructureThatRmseDoesNot) {
    // Same RMSE: a constant offset keeps structure (SSIM stays near its luminance term),
    // inverting the pattern about its mean destroys it (negative covariance: SSIM < 0).
    const ImageF a = pattern(32, 32);
    ImageF inverted = a, offset = a;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        inverted.pixels[i] = 1.0f - a.pixels[i];
    const double e = metrics::rmse(a, inverted);
    for (float& v : offset.pixels)
        v += float(e);
    EXPECT_NEAR(metrics::rmse(a, offset), e, 1e-5);
    EXPECT_LT(metrics::ssim(a, inverted), 0.0);
    EXPECT_GT(metrics::ssim(a, offset), 0.5);
    EXPECT_NEAR(metrics::ssim(a, inverted), metrics::ssim(inverted, a), 1e-12);
}

TEST(MetricsTest, ToneMapIsClampedSrgbOrAces) {
    ImageF hdr = pair({0.0f, 0.5f, 4.0f, 0.002f, 0.18f, 1.0f});
    const ImageF s = metrics::toneMapSrgb(hdr, 1.0, metrics::ToneMap::Clamp);
    EXPECT_NEAR(s.pixels[0], 0.0, 1e-7);
    EXPECT_NEAR(s.pixels[1], 1.055 * std::pow(0.5, 1 / 2.4) - 0.055, 1e-6);
    EXPECT_NEAR(s.pixels[2], 1.0, 1e-7);
    EXPECT_NEAR(s.pixels[3], 12.92 * 0.002, 1e-6);
    const ImageF t = metrics::toneMapSrgb(hdr, 2.0, metrics::ToneMap::Aces);
    const double x = 0.18 * 2.0, aces = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    EXPECT_NEAR(t.pixels[4], 1.055 * std::pow(aces, 1 / 2.4) - 0.055, 1e-6);
}

TEST(MetricsTest, HeatMapRampsFromBlackToWhite) {
    const ImageF a = pair({0, 0, 0, 1, 1, 1}), b = pair({0, 0, 0, 0, 0, 0});
    const ImageF h = metrics::heatMap(a, b, 1.0);
    EXPECT_EQ(h.at(0, 0, 0) + h.at(0, 0, 1) + h.at(0, 0, 2), 0.0f);
    EXPECT_EQ(h.at(1, 0, 0) + h.at(1, 0, 1) + h.at(1, 0, 2), 3.0f);
}

TEST(MetricsTest, StudentPValuesOfClosedForms) {
    // df = 1 is Cauchy: P(|T| > t) = 1 - 2 atan(t) / pi; df = 2: 1 - t / sqrt(t^2 + 2).
    for (double t : {0.1, 1.0, 3.0, 25.0}) {
        EXPECT_NEAR(metrics::studentTwoSidedP(t, 1.0), 1.0 - 2.0 * std::atan(t) / std::numbers::pi,
                    1e-10)
            << t;
        EXPECT_NEAR(metrics::studentTwoSidedP(-t, 2.0), 1.0 - t / std::sqrt(t * t + 2.0), 1e-10)
            << t;
    }
    // Normal: P(|Z| > 1.959964) = 0.05; and t(30) is close to it but wider.
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_NEAR(metrics::studentTwoSidedP(1.959964, inf), 0.05, 1e-6);
    EXPECT_GT(metrics::studentTwoSidedP(1.959964, 30.0), 0.05);
    EXPECT_NEAR(metrics::studentTwoSidedP(2.042272, 30.0), 0.05, 1e-5); // t_{0.975, 30}
}

TEST(MetricsTest, PixelStatsAreMeanAndUnbiasedVariance) {
    const auto st =
        metrics::pixelStats({filled(2, 2, 1.0f), filled(2, 2, 2.0f), filled(2, 2, 6.0f)});
    EXPECT_EQ(st.count, 3);
    EXPECT_NEAR(st.mean.at(1, 1, 2), 3.0, 1e-6);
    EXPECT_NEAR(st.variance.at(0, 1, 0), (4.0 + 1.0 + 9.0) / 2.0, 1e-6);
}

TEST(MetricsTest, WelchTestOfAKnownPixel) {
    // One pixel, a = {1, 2, 3, 4} (mean 2.5, s^2 = 5/3) against a deterministic reference r:
    // t = (2.5 - r) / sqrt(5/12 + floor^2) with 3 degrees of freedom. r = 0: t = 3.873, the
    // two-sided p of t(3) is 0.0305 (hand: 1 - I over the t(3) CDF). Rejected at alpha 0.05
    // with m = 3 tests only if p <= 0.05 / 3: not here; rejected at alpha 0.1 (0.0333).
    std::vector<ImageF> s;
    for (float v : {1.f, 2.f, 3.f, 4.f})
        s.push_back(filled(1, 1, v));
    const auto a = metrics::pixelStats(s);
    const auto ref = metrics::pixelStats({filled(1, 1, 0.0f)});
    metrics::PixelTestOptions o;
    o.absoluteFloor = 0.0;
    o.relativeFloor = 0.0;
    o.alpha = 0.05;
    auto r = metrics::welchPixelTest(a, ref, o);
    // t(3): P(|T| > t) = 1 - (2/pi)(atan(u) + u / (1 + u^2)) with u = t / sqrt(3).
    const double t = 2.5 / std::sqrt(5.0 / 12.0), u = t / std::sqrt(3.0);
    const double p = 1.0 - 2.0 / std::numbers::pi * (std::atan(u) + u / (1.0 + u * u));
    EXPECT_NEAR(r.minP, p, 1e-9);
    EXPECT_EQ(r.rejectedPixels, 0);
    o.alpha = 0.1;
    r = metrics::welchPixelTest(a, ref, o);
    EXPECT_EQ(r.rejectedPixels, 1);
    EXPECT_EQ(r.rejectedValues, 3);
    EXPECT_EQ(r.fraction, 1.0);
}

TEST(MetricsTest, HolmRejectsAtLeastWhatBonferroniDoes) {
    // Three values with p-values about 0.001, 0.02 and 0.04 at alpha 0.05, m = 3: Bonferroni
    // (p <= 0.0167) rejects one; Holm steps down: 0.001 <= 0.05/3, 0.02 <= 0.05/2, 0.04 <=
    // 0.05/1: all three. Samples of +-1 around a mean mu, n = 2: s^2 = 2, t = mu / 1 with 1
    // degree of freedom, p = 1 - 2 atan(mu) / pi: mu = tan(pi/2 (1 - p)).
    std::vector<ImageF> s(2, ImageF(1, 1, 3));
    for (int c = 0; c < 3; ++c) {
        const double p = std::array{0.001, 0.02, 0.04}[c];
        const double mu = std::tan(std::numbers::pi / 2 * (1 - p));
        s[0].pixels[c] = float(mu - 1.0);
        s[1].pixels[c] = float(mu + 1.0);
    }
    metrics::PixelTestOptions o;
    o.absoluteFloor = o.relativeFloor = 0.0;
    o.alpha = 0.05;
    o.correction = metrics::Correction::Bonferroni;
    const auto a = metrics::pixelStats(s), ref = metrics::pixelStats({ImageF(1, 1, 3)});
    EXPECT_EQ(metrics::welchPixelTest(a, ref, o).rejectedValues, 1);
    o.correction = metrics::Correction::Holm;
    EXPECT_EQ(metrics::welchPixelTest(a, ref, o).rejectedValues, 3);
}

TEST(MetricsTest, UnbiasedNoiseIsRarelyRejectedAndABiasIs) {
    // 16 renders of a 32 x 32 image: value = 0.5 + noise (a fixed sequence of +-0.1 or +-0.15,
    // mean near 0 per pixel, s ~ 0.11) against the exact 0.5: no rejections. Shifting the mean
    // by 0.3 (t ~ 0.3 / (0.11 / 4) ~ 11, p of t(15) ~ 1e-8, under the Holm/Bonferroni level
    // 0.01 / 3072 = 3e-6) rejects every pixel; 0.1 (t ~ 3.6, p ~ 3e-3) would not.
    std::vector<ImageF> s, biased;
    for (int k = 0; k < 16; ++k) {
        ImageF img(32, 32, 3), b(32, 32, 3);
        for (std::size_t i = 0; i < img.pixels.size(); ++i) {
            const float noise =
                ((k + i) % 2 ? 0.1f : -0.1f) * (1.0f + 0.5f * float((i * 7 + k) % 3 == 0));
            img.pixels[i] = 0.5f + noise;
            b.pixels[i] = img.pixels[i] + 0.3f;
        }
        s.push_back(img);
        biased.push_back(b);
    }
    const auto ref = metrics::pixelStats({filled(32, 32, 0.5f)});
    const auto ok = metrics::welchPixelTest(metrics::pixelStats(s), ref);
    const auto bad = metrics::welchPixelTest(metrics::pixelStats(biased), ref);
    EXPECT_LT(ok.fraction, 0.01);
    EXPECT_GT(bad.fraction, 0.99);
}

TEST(MetricsTest, MetricNamesAndThresholds) {
    for (const std::string& n : metrics::metricNames())
        EXPECT_TRUE(metrics::isMetricName(n)) << n;
    EXPECT_FALSE(metrics::isMetricName("mse"));
    EXPECT_TRUE(metrics::withinThreshold("rmse", 0.01, 0.01));
    EXPECT_FALSE(metrics::withinThreshold("rmse", 0.011, 0.01));
    EXPECT_TRUE(metrics::withinThreshold("ssim", 0.99, 0.98));
    EXPECT_FALSE(metrics::withinThreshold("psnr", 29.0, 30.0));
    EXPECT_FALSE(metrics::withinThreshold("rmse", std::nan(""), 1.0));
    EXPECT_THROW(metrics::compute("mse", filled(1, 1, 0), filled(1, 1, 0)), Error);
}

} // namespace veil::test
