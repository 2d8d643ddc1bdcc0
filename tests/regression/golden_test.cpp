// Golden image of a known scene (tests/regression/scenes/golden_basic.json) compared in
// linear space with max-abs and RMSE thresholds; on failure the render, the reference and
// the difference are written to build/test-output. The golden file itself is checked: its
// key pixels are asserted against analytic radiance, so a wrong golden cannot pass.
//
// Regenerate (after looking at the new image!): VEIL_UPDATE_GOLDEN=1 veil_regression_tests
#include "frame/renderer.h"
#include "gpu/context.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace veil::test {

namespace {

const double kPi = 3.14159265358979323846;

// f(l,v)(n.l) for the dielectric grey floor (metalness 0), written from the formulas:
// GGX D, height-correlated Smith V, Schlick F with F0 = 0.04, Lambert (1 - F) albedo / pi.
double floorBrdfCos(double albedo, double r, double nl, double nv, double nh, double lh) {
    const double a = r * r, a2 = a * a;
    const double dd = nh * nh * (a2 - 1) + 1;
    const double D = a2 / (kPi * dd * dd);
    const double gv = nl * std::sqrt(nv * nv * (1 - a2) + a2);
    const double gl = nv * std::sqrt(nl * nl * (1 - a2) + a2);
    const double F = 0.04 + 0.96 * std::pow(1 - lh, 5);
    return ((1 - F) * albedo / kPi + D * (0.5 / (gv + gl)) * F) * nl;
}

// Pixel of world (x, z) for the 160x160 top camera of height 8 (row 0 = -z).
int pix(double w) { return static_cast<int>(std::floor((w + 4.0) / 8.0 * 160.0)); }

struct Expected {
    double ambient = 0.1 * 0.5;
    double litFloor = 0.0;
    Expected() {
        // Light from (-1, 1, 0)/sqrt2 onto a horizontal floor seen from straight above.
        const double s = 1.0 / std::sqrt(2.0);
        const double nl = s, nv = 1.0;
        const double hx = -s, hy = s + 1.0, hn = std::sqrt(hx * hx + hy * hy);
        const double nh = hy / hn, lh = (-s * hx + s * hy) / hn;
        litFloor = ambient + 2.0 * floorBrdfCos(0.5, 0.7, nl, nv, nh, lh);
    }
};

class GoldenTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        context_ = std::make_unique<gpu::HeadlessContext>();
        const auto scene =
            scene::loadScene(sourceDir() / "tests/regression/scenes/golden_basic.json");
        frame::Renderer renderer(scene, context_->info());
        renderer.render();
        render_ = renderer.readHdr();
        const auto golden = goldenPath();
        if (std::getenv("VEIL_UPDATE_GOLDEN")) {
            io::writeImage(golden, render_);
            io::writeImage(outputDir() / "golden_basic.png", renderer.readLdr());
        }
        golden_ = io::readImage(golden);
    }
    static std::filesystem::path goldenPath() {
        return sourceDir() / "tests/regression/golden/golden_basic.exr";
    }
    static inline std::unique_ptr<gpu::HeadlessContext> context_;
    static inline ImageF render_, golden_;
};

} // namespace

TEST_F(GoldenTest, RenderMatchesGolden) {
    // Same driver family (llvmpipe) renders the golden and CI; allow filtering differences at
    // edges (max) but almost none on average (RMSE), in linear radiance units.
    const ImageDiff d = compareImages(render_, golden_);
    const bool ok = d.maxAbs <= 0.05 && d.rmse <= 0.002;
    EXPECT_TRUE(ok) << "max-abs " << d.maxAbs << " (<= 0.05), RMSE " << d.rmse
                    << " (<= 0.002); images in "
                    << writeFailureImages("golden_basic", render_, golden_);
}

TEST_F(GoldenTest, GoldenKeyPixelsAreAnalytic) {
    const Expected e;
    // Check the stored golden, and the live render, against the analytic values.
    for (const ImageF* img : {&golden_, &render_}) {
        // 1. Background outside the 6x6 floor.
        const int bx = pix(-3.8), by = pix(0.0);
        EXPECT_NEAR(img->at(bx, by, 0), 0.2, 1e-3);
        EXPECT_NEAR(img->at(bx, by, 1), 0.3, 1e-3);
        EXPECT_NEAR(img->at(bx, by, 2), 0.4, 1e-3);
        // 2. Floor in the box's shadow (x in [0.5, 1.5] for |z| < 0.5): ambient only.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(img->at(pix(1.0), pix(0.0), c), e.ambient, 2e-3);
        // 3. Lit floor: ambient + E * f * N.L.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(img->at(pix(-1.0), pix(-0.2), c), e.litFloor, 2e-3 * e.litFloor + 1e-4);
        // 4. Floor through the emissive filter (alpha 0.5, T = (0, 0.5, 1), emission
        //    (0.3, 0.1, 0)): 0.5 E + (1 - 0.5 + 0.5 T) * floor. The filter is black metal
        //    (F0 = 0): its specular at this angle is below 1e-5, inside the tolerance.
        const double emission[3] = {0.3, 0.1, 0.0}, T[3] = {0.0, 0.5, 1.0};
        for (int c = 0; c < 3; ++c) {
            const double expected = 0.5 * emission[c] + (0.5 + 0.5 * T[c]) * e.litFloor;
            EXPECT_NEAR(img->at(pix(-2.0), pix(1.8), c), expected, 2e-3) << "channel " << c;
        }
    }
}

} // namespace veil::test
