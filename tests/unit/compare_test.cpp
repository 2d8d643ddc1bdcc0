// The comparison library (src/compare) called directly: the error numbers are the metrics'
// (io/metrics.h), the error image is |a - b| x scale sRGB-encoded, the contact sheet lays
// tiles side by side, compare targets are told apart, and the CPU fog reference is composited
// over the background.
#include "base/error.h"
#include "compare/compare.h"
#include "compare/target.h"
#include "io/metrics.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "integrators/cpu_reference.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>

namespace veil::test {

namespace {

ImageF filled(int w, int h, float v) {
    ImageF image(w, h, 3);
    for (float& p : image.pixels)
        p = v;
    return image;
}

// A deterministic image with values in [0, 2).
ImageF ramp(int w, int h, float offset) {
    ImageF image(w, h, 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = std::fmod(0.37f * float(i) + offset, 2.0f);
    return image;
}

} // namespace

TEST(CompareTest, ErrorNumbersAreTheMetrics) {
    const ImageF a = ramp(7, 5, 0.1f), b = ramp(7, 5, 0.3f);
    const compare::ImageError e = compare::compareLinear(a, b);
    EXPECT_EQ(e.rmse, metrics::rmse(a, b));
    EXPECT_EQ(e.psnr, metrics::psnr(a, b));
    EXPECT_EQ(e.peak, metrics::peak(b));
    EXPECT_GT(e.peak, 1.9);
}

TEST(CompareTest, IdenticalImagesHaveInfinitePsnrAndAZeroReferenceNone) {
    const ImageF a = ramp(4, 3, 0.2f);
    const compare::ImageError same = compare::compareLinear(a, a);
    EXPECT_EQ(same.rmse, 0.0);
    EXPECT_TRUE(std::isinf(same.psnr));
    const compare::ImageError dark = compare::compareLinear(a, filled(4, 3, 0.0f));
    EXPECT_TRUE(std::isnan(dark.psnr));
    EXPECT_EQ(dark.peak, 0.0);
}

TEST(CompareTest, MetricsPeakIsTheLargestRgbValue) {
    ImageF a(2, 1, 4);
    a.pixels = {0.1f, 0.2f, 0.3f, 9.0f, 0.5f, 0.25f, 0.0f, 7.0f}; // alpha is not RGB
    EXPECT_FLOAT_EQ(float(metrics::peak(a)), 0.5f);
}

TEST(CompareTest, SrgbEncodeIsTheIecTransferFunction) {
    EXPECT_FLOAT_EQ(metrics::srgbEncode(0.0), 0.0f);
    EXPECT_FLOAT_EQ(metrics::srgbEncode(1.0), 1.0f);
    EXPECT_FLOAT_EQ(metrics::srgbEncode(2.0), 1.0f);
    EXPECT_FLOAT_EQ(metrics::srgbEncode(-1.0), 0.0f);
    EXPECT_FLOAT_EQ(metrics::srgbEncode(0.002), float(12.92 * 0.002));
    EXPECT_NEAR(metrics::srgbEncode(0.5), 1.055 * std::pow(0.5, 1.0 / 2.4) - 0.055, 1e-7);
}

TEST(CompareTest, ErrorImageIsScaledAbsoluteErrorSrgbEncoded) {
    const ImageF a = filled(3, 2, 0.5f), b = filled(3, 2, 0.45f);
    const ImageF e = compare::errorImage(a, b);
    ASSERT_EQ(e.channels, 3);
    for (float v : e.pixels)
        EXPECT_FLOAT_EQ(v, metrics::srgbEncode((0.5f - 0.45f) * compare::kErrorImageScale));
    const ImageF big = compare::errorImage(a, filled(3, 2, 0.0f), 4.0f); // 2.0 clamps to 1
    for (float v : big.pixels)
        EXPECT_FLOAT_EQ(v, 1.0f);
    EXPECT_THROW(compare::errorImage(a, filled(2, 2, 0.0f)), Error);
}

TEST(CompareTest, ContactSheetPutsTilesSideBySideWithBlackGaps) {
    const ImageF sheet = compare::contactSheet({filled(2, 3, 0.25f), filled(4, 3, 0.75f)}, 1);
    EXPECT_EQ(sheet.width, 2 + 1 + 4);
    EXPECT_EQ(sheet.height, 3);
    for (int y = 0; y < 3; ++y) {
        EXPECT_EQ(sheet.at(1, y, 0), 0.25f);
        EXPECT_EQ(sheet.at(2, y, 1), 0.0f);
        EXPECT_EQ(sheet.at(3, y, 2), 0.75f);
        EXPECT_EQ(sheet.at(6, y, 0), 0.75f);
    }
    EXPECT_THROW(compare::contactSheet({filled(2, 3, 0.0f), filled(2, 2, 0.0f)}), Error);
    EXPECT_THROW(compare::contactSheet({}), Error);
}

TEST(CompareTest, LabelledSheetIsAGridWithTextUnderEachTile) {
    // 7 tiles of 160x90 with 2 label lines: text 10 px (160 / 16), line pitch 12, strip
    // 2 x 12 + 5 = 29, cell (160 + 4) x (90 + 29 + 4). Sheet aspect by column count: 3 columns
    // 492 x 369 (1.33), 4 columns 656 x 246 (2.67), 2 columns 0.67: 3 is nearest 16:9 (1.78)
    // in log ratio.
    std::vector<ImageF> tiles;
    std::vector<std::vector<std::string>> labels;
    for (int i = 0; i < 7; ++i) {
        tiles.push_back(filled(160, 90, 0.25f));
        labels.push_back({"moment-p4", i == 3 ? "" : "RMSE 0.0123"});
    }
    labels[5].clear(); // no label: its strip stays black
    const ImageF sheet = compare::labelledContactSheet(tiles, labels);
    const int cellW = 164, cellH = 90 + 29 + 4;
    const int columns = 3;
    EXPECT_EQ(sheet.width, 3 * cellW - 4);
    EXPECT_EQ(sheet.height, 3 * cellH - 4);
    // Lit pixels in each tile's strip, row by row of text.
    const auto lit = [&](int tile, int line) {
        const int x0 = (tile % columns) * cellW, y0 = (tile / columns) * cellH + 90 + 2 + 12 * line;
        int n = 0;
        for (int y = y0; y < y0 + 12; ++y)
            for (int x = x0; x < x0 + 160; ++x)
                n += sheet.at(x, y, 0) > 0.5f;
        return n;
    };
    for (int i = 0; i < 7; ++i) {
        EXPECT_EQ(lit(i, 0) > 30, i != 5) << "tile " << i;
        EXPECT_EQ(lit(i, 1) > 30, i != 5 && i != 3) << "tile " << i;
    }
    // The tiles themselves are untouched.
    EXPECT_EQ(sheet.at(cellW + 80, 45, 1), 0.25f);
    EXPECT_THROW(compare::labelledContactSheet(tiles, {{"a"}}), Error);
}

TEST(CompareTest, CompareTargetsAreToldApart) {
    using Kind = compare::CompareTarget::Kind;
    EXPECT_EQ(compare::parseCompareTarget("").kind, Kind::None);
    EXPECT_EQ(compare::parseCompareTarget("cpu").kind, Kind::Cpu);
    EXPECT_EQ(compare::parseCompareTarget("reference").kind, Kind::Technique);
    EXPECT_EQ(compare::parseCompareTarget("moment-p4").kind, Kind::Technique);
    EXPECT_EQ(compare::parseCompareTarget("ref.exr").kind, Kind::File);
    EXPECT_EQ(compare::parseCompareTarget("dir/ref").kind, Kind::File);
    const compare::CompareTarget s = compare::parseCompareTarget("shadows:reference");
    EXPECT_EQ(s.kind, Kind::Shadows);
    EXPECT_EQ(s.shadows, "reference");
}

TEST(CompareTest, CheckedTargetsNameTheProblem) {
    scene::Scene noFog;
    noFog.sourcePath = "empty.json";
    try {
        compare::checkCompareTarget(compare::parseCompareTarget("cpu"), noFog);
        FAIL() << "a scene without volumes has no CPU fog reference";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("has no volumes"), std::string::npos) << e.what();
    }
    try {
        compare::checkCompareTarget(compare::parseCompareTarget("missing/ref.exr"), noFog);
        FAIL() << "a missing file is refused";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no such image file"), std::string::npos) << e.what();
    }
}

// The CPU reference used by `veil render --compare-to cpu` and by regression cases with the
// reference "cpu": the fog's radiance plus the background seen through its transmittance.
TEST(CompareTest, CpuFogIsCompositedOverTheBackground) {
    const nlohmann::json doc = {
        {"render", {{"width", 12}, {"height", 8}, {"background", {0.2, 0.5, 0.9}}}},
        {"cameras", {{{"name", "c"}, {"position", {0, 1, 4}}, {"target", {0, 0.5, 0}}}}},
        {"lights", {{{"type", "directional"}, {"direction", {0.3, -1, -0.2}}, {"intensity", 2}}}},
        {"volumes", {{{"name", "haze"}, {"procedural", "homogeneous"}, {"density_scale", 0.02}}}}};
    const scene::Scene s = scene::parseScene(doc, sourceDir());
    const scene::Camera camera = s.camera("");
    const ImageF out = compare::cpuFogOverBackground(s, camera, 12, 8, 64);
    const ImageF fog = volume::CpuFogReference(s, {}).render(camera, 12, 8, 64);
    ASSERT_EQ(out.channels, 3);
    ASSERT_EQ(fog.channels, 4);
    double transmittance = 0.0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 12; ++x) {
            transmittance += fog.at(x, y, 3) / 96.0;
            for (int c = 0; c < 3; ++c)
                EXPECT_FLOAT_EQ(out.at(x, y, c),
                                fog.at(x, y, c) + fog.at(x, y, 3) * s.render.background[c]);
        }
    EXPECT_GE(transmittance, 0.0);
    EXPECT_LT(transmittance, 1.0); // the background is dimmed by the fog
}

} // namespace veil::test
