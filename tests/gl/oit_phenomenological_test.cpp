// OIT `phenomenological` [McGuire16, McGuire17] against values it did not produce: the exact
// product of transmissions ([McGuire16 Fig. 2] colored glass bars), the resolve equations evaluated
// by hand in double precision ([McGuire16 Eq. 2-5], [McGuire17 Eq. 14]), Snell's law [McGuire16 Eq.
// 8-9] for the refraction shift, Eq. 7 for the presence and absence of diffusion, and a
// double-precision sorted composite of planes [McGuire16 Eq. 1] for the error of the approximation.
//
// All scenes: orthographic camera straight down from y = 10 over an 8 x 8 area at 128 x 128
// pixels (16 pixels per unit; image x = world x, image row = world z), no lights, ambient 0,
// so each surface's reflected radiance is its emission.
#include "gl_fixture.h"

#include "base/error.h"
#include "frame/renderer.h"
#include "io/image_io.h"
#include "oit/cpu/phenomenological.h"
#include "oit/phenomenological/phenomenological.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace veil::test {

namespace {

constexpr int kSize = 128;
constexpr double kPixelsPerUnit = 16.0;

using Rgb = std::array<double, 3>;

// A horizontal plane (normal +y) for the scenes and for the CPU composite.
struct Plane {
    double cx, cz, sx, sz, height;
    Rgb emission{0, 0, 0};
    double alpha = 1.0;
    Rgb transmission{0, 0, 0};
    double collimation = 1.0;
    double ior = 1.0;
    bool opaque = false;
};

double worldOf(int pixel) { return -4.0 + (pixel + 0.5) / kPixelsPerUnit; }

bool covers(const Plane& p, int x, int y) {
    return std::abs(worldOf(x) - p.cx) < 0.5 * p.sx && std::abs(worldOf(y) - p.cz) < 0.5 * p.sz;
}

nlohmann::json toJson(const Rgb& c) { return {c[0], c[1], c[2]}; }

nlohmann::json makeScene(const std::vector<Plane>& planes, const Rgb& background,
                         double tiltDegrees = 0.0) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 128, "height": 128, "ambient": 0, "tonemap": "clamp"},
      "cameras": [{"name": "top", "type": "orthographic", "position": [0, 10, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 8, "near": 1,
                   "far": 20}],
      "materials": {}, "objects": []})");
    doc["render"]["background"] = toJson(background);
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const Plane& p = planes[i];
        const std::string name = fmt::format("m{}", i);
        nlohmann::json m = {{"base_color", 0.0}, {"emission", toJson(p.emission)}};
        if (!p.opaque) {
            m["alpha"] = p.alpha;
            m["transmission"] = toJson(p.transmission);
            m["collimation"] = p.collimation;
            m["ior"] = p.ior;
        }
        doc["materials"][name] = m;
        nlohmann::json object = {{"shape", {{"type", "plane"}, {"size", {p.sx, p.sz}}}},
                                 {"material", name}};
        object["transform"] = {{"translate", {p.cx, p.height, p.cz}}};
        if (tiltDegrees != 0.0 && !p.opaque)
            object["transform"]["rotate"] = {0.0, 0.0, tiltDegrees};
        doc["objects"].push_back(object);
    }
    return doc;
}

// [McGuire16 Eq. 1] for the planes covering a pixel, sorted back to front (double precision).
Rgb sortedComposite(std::vector<Plane> planes, const Rgb& background, int x, int y) {
    std::sort(planes.begin(), planes.end(),
              [](const Plane& a, const Plane& b) { return a.height < b.height; });
    Rgb L = background;
    for (const Plane& p : planes) {
        if (!covers(p, x, y)) continue;
        for (int c = 0; c < 3; ++c) {
            if (p.opaque)
                L[c] = p.emission[c];
            else
                L[c] = p.alpha * (p.emission[c] + p.transmission[c] * L[c]) + (1 - p.alpha) * L[c];
        }
    }
    return L;
}

double maxOf(const Rgb& v) { return std::max({v[0], v[1], v[2]}); }

// The technique's own model (src/oit/cpu/phenomenological.h) for the planes covering a
// pixel, without refraction or diffusion. Window depth f of an orthographic camera (near 1,
// far 20, eye at y = 10) for the Eq. 5 weights.
Rgb phenomenologicalComposite(const std::vector<Plane>& planes, const Rgb& background, int x, int y,
                              bool selfModulation) {
    glm::dvec3 bkg(background[0], background[1], background[2]);
    std::vector<oit::cpu::PhenomenologicalLayer> layers;
    for (const Plane& p : planes) {
        if (!covers(p, x, y)) continue;
        const glm::dvec3 E(p.emission[0], p.emission[1], p.emission[2]);
        if (p.opaque) {
            bkg = E;
            continue;
        }
        layers.push_back({((10.0 - p.height) - 1.0) / 19.0, p.alpha * E, p.alpha,
                          glm::dvec3(p.transmission[0], p.transmission[1], p.transmission[2])});
    }
    oit::cpu::PhenomenologicalOptions options;
    options.selfModulation = selfModulation;
    const glm::dvec3 r = oit::cpu::phenomenologicalResolve(layers, bkg, options);
    return {r.x, r.y, r.z};
}

double rmseAgainst(const ImageF& img, const std::vector<Plane>& planes, const Rgb& background) {
    double sum = 0.0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const Rgb e = sortedComposite(planes, background, x, y);
            for (int c = 0; c < 3; ++c)
                sum += std::pow(img.at(x, y, c) - e[c], 2);
        }
    return std::sqrt(sum / (3.0 * kSize * kSize));
}

// Pixels strictly between 5% and 95% of the step on row y (a sharp edge has none).
int edgeWidth(const ImageF& img, int y, double low, double high) {
    int n = 0;
    for (int x = 8; x < kSize - 8; ++x) {
        const double v = (img.at(x, y, 1) - low) / (high - low);
        if (v > 0.05 && v < 0.95) ++n;
    }
    return n;
}

bool allFinite(const ImageF& img) {
    for (float v : img.pixels)
        if (!std::isfinite(v)) return false;
    return true;
}

} // namespace

class OitPhenomenologicalTest : public GlTest {
protected:
    // Renders with the given technique and parameters; writes an LDR PNG to look at.
    static ImageF render(const nlohmann::json& doc, const std::string& technique,
                         const std::string& png, const oit::PhenomenologicalParams& params = {}) {
        const scene::Scene sc = scene::parseScene(doc, sourceDir());
        // The technique's defaults, except where the test's params differ from the struct's.
        nlohmann::json props = oit::toProperties(params);
        const nlohmann::json base = oit::toProperties({});
        for (auto it = base.begin(); it != base.end(); ++it)
            if (props[it.key()] == it.value()) props.erase(it.key());
        frame::Renderer renderer(sc, info(), {kSize, kSize, "", technique, props});
        renderer.render();
        io::writeImage(outputDir() / (png + ".png"), renderer.readLdr());
        return renderer.readHdr();
    }
};

// [McGuire16 Fig. 2]: two layers of non-reflective colored glass bars. Beta is an exact product, so
// the result must equal sorted two-pass transparency: background * T1 * T2.
TEST_F(OitPhenomenologicalTest, ColoredGlassBarsEqualSortedTransmission) {
    const Rgb bg{1.0, 0.9, 0.8};
    std::vector<Plane> planes = {
        {0, -1.5, 8, 1.5, 2.0, {0, 0, 0}, 1.0, {0.9, 0.25, 0.1}},
        {0, 1.5, 8, 1.5, 2.0, {0, 0, 0}, 1.0, {0.2, 0.7, 0.95}},
        {-1.5, 0, 1.5, 8, 3.0, {0, 0, 0}, 1.0, {0.3, 0.85, 0.4}},
        {1.5, 0, 1.5, 8, 3.0, {0, 0, 0}, 1.0, {0.95, 0.6, 0.2}},
    };
    const ImageF img = render(makeScene(planes, bg), "phenomenological", "phen_glass_bars");
    VEIL_EXPECT_NO_GL_ERROR();
    double maxErr = 0.0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const Rgb e = sortedComposite(planes, bg, x, y);
            for (int c = 0; c < 3; ++c)
                maxErr = std::max(maxErr, std::abs(static_cast<double>(img.at(x, y, c)) - e[c]));
        }
    RecordProperty("max_abs_error", std::to_string(maxErr));
    EXPECT_LE(maxErr, 1e-3);
    // Not a blank image: the overlap of bars 0 and 2 is dark red/green mixed.
    const int x = 40, y = 40; // world (-1.47, -1.47): both bars
    EXPECT_NEAR(img.at(x, y, 0), 1.0 * 0.9 * 0.3, 1e-3);
    EXPECT_NEAR(img.at(x, y, 1), 0.9 * 0.25 * 0.85, 1e-3);
}

// A single emissive, partially covering, colored-transmission surface: [McGuire16 Eq. 3] with
// U' = A_rgb / A_a (Eq. 4) = E / (1 - mean t), self-modulated by [McGuire17 Eq. 14].
TEST_F(OitPhenomenologicalTest, SingleEmissiveSurfaceMatchesResolveEquations) {
    const Rgb bg{0.3, 0.6, 0.9};
    const Rgb E{2.0, 1.0, 0.5}, T{0.2, 0.5, 0.8};
    const double a = 0.6;
    const std::vector<Plane> planes = {{0, 0, 4, 4, 2.0, E, a, T}};
    for (bool selfModulation : {true, false}) {
        oit::PhenomenologicalParams params;
        params.selfModulation = selfModulation;
        const ImageF img =
            render(makeScene(planes, bg), "phenomenological",
                   selfModulation ? "phen_single_selfmod" : "phen_single_noselfmod", params);
        // By hand: beta = 1 - a + a T; U = E / (1 - mean T) (w cancels for one surface);
        // s = 1/2 + max(beta, 1e-3) / max(2e-3, 2 max beta).
        Rgb beta, expected;
        const double tMean = (T[0] + T[1] + T[2]) / 3.0;
        for (int c = 0; c < 3; ++c)
            beta[c] = 1 - a + a * T[c];
        for (int c = 0; c < 3; ++c) {
            const double s = selfModulation ? 0.5 + beta[c] / (2 * maxOf(beta)) : 1.0;
            expected[c] = bg[c] * beta[c] + (1 - beta[c]) * E[c] / (1 - tMean) * s;
        }
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(img.at(64, 64, c), expected[c], 2e-3 * std::max(1.0, expected[c]))
                << "channel " << c << " selfModulation " << selfModulation;
            EXPECT_NEAR(img.at(4, 4, c), bg[c], 1e-3) << "outside the surface";
        }
    }
}

// [McGuire16 Eq. 7]: a decollimated surface (c = 0) blurs a background edge; c = 1, diffusion off,
// or the background pressed against the surface (|z_X - z_B| << k_1) leave it sharp.
TEST_F(OitPhenomenologicalTest, DiffusionBlursEdgeOnlyWhenDecollimatedAndDistant) {
    const Rgb bg{0, 0, 0};
    auto scene = [&](double collimation, double glassHeight) {
        Plane lit{2, 0, 4, 8, 0.0, {1, 1, 1}};
        lit.opaque = true;
        Plane glass{0, 0, 8, 8, glassHeight, {0, 0, 0}, 1.0, {0.8, 0.8, 0.8}};
        glass.collimation = collimation;
        return makeScene({lit, glass}, bg);
    };
    // Expected D = k0 * netCoverage * (1 - c) * dz / (k1 + dz) * 16 px = 5.2 px for dz = 3.
    const ImageF blurred = render(scene(0.0, 3.0), "phenomenological", "phen_diffusion_c0");
    const ImageF sharp = render(scene(1.0, 3.0), "phenomenological", "phen_diffusion_c1");
    const ImageF pressed = render(scene(0.0, 0.02), "phenomenological", "phen_diffusion_pressed");
    oit::PhenomenologicalParams off;
    off.diffusion = false;
    const ImageF disabled = render(scene(0.0, 3.0), "phenomenological", "phen_diffusion_off", off);
    const int row = 64;
    const int wBlurred = edgeWidth(blurred, row, 0.0, 0.8);
    RecordProperty("blurred_edge_width_px", wBlurred);
    EXPECT_GE(wBlurred, 3);
    EXPECT_LE(wBlurred, 12);
    EXPECT_EQ(edgeWidth(sharp, row, 0.0, 0.8), 0);
    EXPECT_EQ(edgeWidth(pressed, row, 0.0, 0.8), 0);
    EXPECT_EQ(edgeWidth(disabled, row, 0.0, 0.8), 0);
    // The blur is a normalized filter: far from the edge the plateau stays 0.8.
    EXPECT_NEAR(blurred.at(110, row, 1), 0.8, 2e-3);
    EXPECT_NEAR(blurred.at(20, row, 1), 0.0, 1e-3);
}

// [McGuire16 sec. 5 "Diffuse"] (Listing 2): the gather skips taps whose own diffusion radius is
// smaller than their distance, so a bright object pressed against frosted glass (D ~ 0) stays
// sharp and does not bleed into the diffused dark floor beside it.
TEST_F(OitPhenomenologicalTest, DiffusionGatherIsOcclusionAware) {
    nlohmann::json doc = makeScene({}, {0, 0, 0});
    doc["materials"] = nlohmann::json::parse(R"({
      "dark": {"base_color": 0, "emission": [0, 0, 0]},
      "bright": {"base_color": 0, "emission": [1, 1, 1]},
      "frosted": {"base_color": 0, "transmission": [0.8, 0.8, 0.8], "collimation": 0}})");
    doc["objects"] = nlohmann::json::parse(R"([
      {"shape": {"type": "plane", "size": [8, 8]}, "material": "dark"},
      {"shape": {"type": "box", "size": [4, 2.98, 8]}, "material": "bright",
       "transform": {"translate": [-2, 1.49, 0]}},
      {"shape": {"type": "plane", "size": [8, 8]}, "material": "frosted",
       "transform": {"translate": [0, 3, 0]}}])");
    const ImageF img = render(doc, "phenomenological", "phen_diffusion_pressed_edge");
    const int row = 64;
    EXPECT_EQ(edgeWidth(img, row, 0.0, 0.8), 0);
    EXPECT_NEAR(img.at(63, row, 1), 0.8, 2e-3); // pressed box, sharp
    EXPECT_NEAR(img.at(64, row, 1), 0.0, 1e-3); // diffused floor, no bleeding from the box
    EXPECT_NEAR(img.at(66, row, 1), 0.0, 1e-3);
}

// [McGuire16 Eq. 8-9]: a glass plane tilted 20 degrees about z (normal toward -x) refracts the eye
// ray toward +x, so the background appears shifted toward -x by
//   delta = R.x / |R.z| * Delta z * 16 px,  R = refract((0,-1,0) in view, n, 1 / ior).
TEST_F(OitPhenomenologicalTest, RefractionShiftsBackgroundAsSnellPredicts) {
    const Rgb bg{0, 0, 0};
    Plane lit{2, 0, 4, 8, 0.0, {1, 1, 1}};
    lit.opaque = true;
    Plane glass{0, 0, 8, 8, 3.0, {0, 0, 0}, 1.0, {0.9, 0.9, 0.9}};
    glass.ior = 1.5;
    const ImageF img =
        render(makeScene({lit, glass}, bg, 20.0), "phenomenological", "phen_refraction");
    glass.ior = 1.0;
    const ImageF straight =
        render(makeScene({lit, glass}, bg, 20.0), "phenomenological", "phen_refraction_eta1");

    const double pi = 3.14159265358979323846, th = 20.0 * pi / 180.0, eta = 1.0 / 1.5;
    // View space: I = (0,0,-1), n = (-sin th, 0, cos th) (rotation about world z tilts the
    // +y normal toward -x; image x = world x).
    const double cosi = std::cos(th);
    const double k = 1.0 - eta * eta * (1.0 - cosi * cosi);
    const double coef = eta * cosi - std::sqrt(k);
    const double Rx = coef * -std::sin(th), Rz = -eta + coef * cosi;
    const double expectedShift = Rx / std::abs(Rz) * 2.0 * kPixelsPerUnit;

    // Edge position from the integral of the normalized step over a window (exact under the
    // bilinear sampling of the resolve).
    auto edgeAt = [](const ImageF& im, double plateau) {
        double sum = 0.0;
        for (int x = 40; x < 88; ++x)
            sum += im.at(x, 64, 1) / plateau;
        return 88.0 - sum;
    };
    const double e0 = edgeAt(straight, 0.9), e1 = edgeAt(img, 0.9);
    RecordProperty("expected_shift_px", std::to_string(expectedShift));
    RecordProperty("measured_shift_px", std::to_string(e0 - e1));
    EXPECT_NEAR(e0, 64.0, 0.05); // no shift for eta = 1
    EXPECT_GT(expectedShift, 3.0);
    EXPECT_NEAR(e0 - e1, expectedShift, 0.1);
}

// [McGuire17 sec. 4.3.2] with the weights of emit.glsl (RT2 = sum c w delta, divided by A_a): the
// tilted glass of the test above (c_1 = 1 - 0.5 = 0.5, Eq. 5 weight clamped at 30) under a
// parallel non-refracting pane (ior 1, delta 0; c_2 = 0.5 (1 - 0.6) = 0.2, w_2 from Eq. 5 at
// its depth) shifts the background by delta_1 c_1 w_1 / (c_1 w_1 + c_2 w_2), about 0.96 of
// the single pane's shift (a coverage-only average would give c_1 / (c_1 + c_2) = 0.71).
// Tolerance: the 0.1 px of the single-pane test plus w_2's change across the edge window
// (the panes are tilted: +-0.03 in window depth, < 0.05 px).
TEST_F(OitPhenomenologicalTest, RefractionOffsetsAveragedWithReflectionWeights) {
    const Rgb bg{0, 0, 0};
    Plane lit{2, 0, 4, 8, 0.0, {1, 1, 1}};
    lit.opaque = true;
    Plane glass{0, 0, 8, 8, 3.0, {0, 0, 0}, 1.0, {0.5, 0.5, 0.5}};
    glass.ior = 1.5;
    Plane pane{0, 0, 8, 8, 4.0, {0, 0, 0}, 0.5, {0.6, 0.6, 0.6}};
    const ImageF img =
        render(makeScene({lit, glass, pane}, bg, 20.0), "phenomenological", "phen_refr_avg");
    glass.ior = 1.0;
    const ImageF straight =
        render(makeScene({lit, glass, pane}, bg, 20.0), "phenomenological", "phen_refr_avg1");

    const double pi = 3.14159265358979323846, th = 20.0 * pi / 180.0, eta = 1.0 / 1.5;
    const double cosi = std::cos(th);
    const double k = 1.0 - eta * eta * (1.0 - cosi * cosi);
    const double coef = eta * cosi - std::sqrt(k);
    const double Rx = coef * -std::sin(th), Rz = -eta + coef * cosi;
    const double shift1 = Rx / std::abs(Rz) * 2.0 * kPixelsPerUnit; // the glass alone
    // [McGuire16 Eq. 5] at a plane of height h tilted th about z, at world x (orthographic camera
    // at y = 10, near 1, far 20).
    auto weight = [&](double c, double h, double x) {
        const double f = ((10.0 - (h + x * std::tan(th))) - 1.0) / 19.0;
        const double tmp = 10.0 * (1.0 - 0.99 * f) * c;
        return std::clamp(tmp * tmp * tmp, 0.01, 30.0);
    };
    const double xEdge = worldOf(64) - shift1 / kPixelsPerUnit; // where the edge is seen
    const double cw1 = 0.5 * weight(0.5, 3.0, xEdge), cw2 = 0.2 * weight(0.2, 4.0, xEdge);
    const double expected = shift1 * cw1 / (cw1 + cw2);
    const double coverageOnly = shift1 * 0.5 / 0.7;

    const double plateau = 0.5 * 0.8; // beta = (1 - 1 + 0.5) (1 - 0.5 + 0.3), U' = 0
    auto edgeAt = [&](const ImageF& im) {
        double sum = 0.0;
        for (int x = 40; x < 88; ++x)
            sum += im.at(x, 64, 1) / plateau;
        return 88.0 - sum;
    };
    const double e0 = edgeAt(straight), e1 = edgeAt(img);
    RecordProperty("expected_shift_px", std::to_string(expected));
    RecordProperty("measured_shift_px", std::to_string(e0 - e1));
    EXPECT_NEAR(e0, 64.0, 0.05);
    EXPECT_NEAR(img.at(100, 64, 1), plateau, 1e-3);
    EXPECT_GT(std::abs(expected - coverageOnly), 0.6); // 4x the tolerance: tells them apart
    EXPECT_NEAR(e0 - e1, expected, 0.15);
}

// Many bright overlapping surfaces overflow the float16 A sums: the resolve's guards keep the
// image finite and non-negative.
TEST_F(OitPhenomenologicalTest, ManyOverlappingSurfacesStayFinite) {
    std::vector<Plane> planes;
    for (int i = 0; i < 120; ++i) {
        const double t = 0.1 + 0.7 * ((i * 37) % 11) / 10.0;
        planes.push_back({0.02 * (i % 7),
                          0.0,
                          6.0,
                          6.0,
                          0.5 + 0.06 * i,
                          {4000.0 + 100 * i, 20000.0, 1e4},
                          0.5 + 0.004 * i,
                          {t, 0.5 * t, 0.2}});
    }
    const ImageF img = render(makeScene(planes, {1, 1, 1}), "phenomenological", "phen_overflow");
    EXPECT_TRUE(allFinite(img));
    float lowest = 0.0f;
    for (float v : img.pixels)
        lowest = std::min(lowest, v);
    EXPECT_GE(lowest, 0.0f);
}

// Error of the approximation against the exact sorted composite of a multi-layer scene, with
// the technique's own resolve equations (evaluated in double) as a tight check and unsorted
// `blend` as the baseline.
TEST_F(OitPhenomenologicalTest, MultiLayerRmseAgainstSortedComposite) {
    const Rgb bg{0.4, 0.45, 0.5};
    Plane floor{-2, 0, 4, 8, 0.0, {0.9, 0.6, 0.3}};
    floor.opaque = true;
    // Submission order front to back: worst case for unsorted blending.
    const std::vector<Plane> planes = {
        floor,
        {0.5, 0.5, 4, 4, 4.0, {0.2, 0.8, 0.3}, 0.5, {0.6, 0.6, 0.6}},
        {-0.5, 0.0, 4, 5, 3.0, {0.9, 0.2, 0.2}, 0.7, {0.5, 0.1, 0.1}},
        {0.0, -1.0, 5, 3, 2.0, {0.1, 0.2, 0.9}, 0.6, {0.1, 0.3, 0.8}},
        {1.0, 1.0, 3, 3, 1.0, {0.8, 0.8, 0.2}, 0.4, {0.0, 0.0, 0.0}},
    };
    const nlohmann::json doc = makeScene(planes, bg);
    const ImageF phen = render(doc, "phenomenological", "phen_multilayer");
    const ImageF blend = render(doc, "blend", "phen_multilayer_blend");
    // The reference itself: blending submitted back to front is exact [McGuire16 sec. 2].
    std::vector<Plane> backToFront = {planes[0], planes[4], planes[3], planes[2], planes[1]};
    const ImageF sorted = render(makeScene(backToFront, bg), "blend", "phen_multilayer_sorted");
    EXPECT_LE(rmseAgainst(sorted, planes, bg), 1e-3);
    const double rmsePhen = rmseAgainst(phen, planes, bg);
    oit::PhenomenologicalParams noSelfModulation;
    noSelfModulation.selfModulation = false;
    const double rmseNoSelfMod = rmseAgainst(
        render(doc, "phenomenological", "phen_multilayer_noselfmod", noSelfModulation), planes, bg);
    RecordProperty("rmse_phenomenological_no_self_modulation", std::to_string(rmseNoSelfMod));
    const double rmseBlend = rmseAgainst(blend, planes, bg);
    double maxModel = 0.0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const Rgb e = phenomenologicalComposite(planes, bg, x, y, true);
            for (int c = 0; c < 3; ++c)
                maxModel =
                    std::max(maxModel, std::abs(phen.at(x, y, c) - e[c]) / std::max(1.0, e[c]));
        }
    RecordProperty("rmse_phenomenological", std::to_string(rmsePhen));
    RecordProperty("rmse_blend_unsorted", std::to_string(rmseBlend));
    std::printf("[phen] RMSE vs sorted: phenomenological %.5f (no self-modulation %.5f), "
                "unsorted blend %.5f; max rel. error vs the model's own equations %.2e\n",
                rmsePhen, rmseNoSelfMod, rmseBlend, maxModel);
    EXPECT_LE(maxModel, 3e-3);
    // Measured 0.0974 (unsorted blend: 0.1145) on llvmpipe; the error is the model's (Eq. 4
    // weights instead of order), not precision, as the check above shows.
    EXPECT_LE(rmsePhen, 0.11);
    EXPECT_LT(rmsePhen, rmseBlend);
}

TEST_F(OitPhenomenologicalTest, BadParametersThrowError) {
    oit::PhenomenologicalParams bad;
    bad.k1 = 0.0f;
    EXPECT_THROW(bad.validate(), Error);
    bad = {};
    bad.maxDiffusionPixels = 0;
    EXPECT_THROW(
        render(makeScene({{0, 0, 2, 2, 1.0}}, {0, 0, 0}), "phenomenological", "phen_bad", bad),
        Error);
}

} // namespace veil::test

namespace veil::test {

// [McGuire16 sec. 5 "Upsample"]: particles accumulated at 1/2 and 1/4 resolution and joint-
// bilateral upsampled stay close to the full-resolution result, and an opaque box above the
// smoke keeps a clean edge (no smoke leaking onto it from the low-resolution blocks).
TEST_F(OitPhenomenologicalTest, ReducedResolutionParticlesMatchFullResolution) {
    nlohmann::json doc = makeScene({}, {0.1, 0.1, 0.1});
    doc["materials"] = nlohmann::json::parse(R"({
      "floor": {"base_color": 0, "emission": [0.2, 0.25, 0.3]},
      "box": {"base_color": 0, "emission": [0.9, 0.9, 0.9]},
      "smoke": {"base_color": 0, "emission": [0.8, 0.4, 0.2], "alpha": 0.3,
                "transmission": [0.2, 0.2, 0.2]},
      "glass": {"base_color": 0, "emission": [0, 0, 0], "transmission": [0.3, 0.9, 0.6]}})");
    doc["objects"] = nlohmann::json::parse(R"([
      {"shape": {"type": "plane", "size": [8, 8]}, "material": "floor"},
      {"shape": {"type": "box", "size": [1.4, 1, 2.6]}, "material": "box",
       "transform": {"translate": [0.55, 4.0, -0.2], "rotate": [0, 30, 0]}},
      {"shape": {"type": "particles", "count": 300, "radius": 2.0, "particle_size": 0.4,
                 "seed": 3}, "material": "smoke", "transform": {"translate": [0, 2, 0]}},
      {"shape": {"type": "plane", "size": [3, 8]}, "material": "glass",
       "transform": {"translate": [-2.5, 5, 0]}}])");
    oit::PhenomenologicalParams params;
    const ImageF full = render(doc, "phenomenological", "phen_particles_full", params);
    params.particleDownsample = 2;
    const ImageF half = render(doc, "phenomenological", "phen_particles_half", params);
    params.particleDownsample = 4;
    const ImageF quarter = render(doc, "phenomenological", "phen_particles_quarter", params);
    VEIL_EXPECT_NO_GL_ERROR();

    const ImageDiff dHalf = compareImages(half, full), dQuarter = compareImages(quarter, full);
    // The box: world x in 0.55 +- ~1, nearer than the smoke. Its pixels far from the smoke in
    // the full image must match full resolution; measure all box pixels (emission 0.9).
    double boxMax = 0.0;
    int boxPixels = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            if (std::abs(full.at(x, y, 0) - 0.9f) < 1e-3f &&
                std::abs(full.at(x, y, 2) - 0.9f) < 1e-3f) {
                ++boxPixels;
                boxMax =
                    std::max(boxMax, static_cast<double>(std::abs(quarter.at(x, y, 2) - 0.9f)));
            }
    std::printf(
        "[phen] particles: RMSE 1/2 %.5f, 1/4 %.5f vs full; box pixels %d, max change %.4f\n",
        dHalf.rmse, dQuarter.rmse, boxPixels, boxMax);
    RecordProperty("rmse_half", std::to_string(dHalf.rmse));
    RecordProperty("rmse_quarter", std::to_string(dQuarter.rmse));
    EXPECT_GT(boxPixels, 500);
    EXPECT_LE(boxMax, 0.01);        // measured 0.0021 (0.47 without the depth key)
    EXPECT_LE(dHalf.rmse, 0.01);    // measured 0.0040
    EXPECT_LE(dQuarter.rmse, 0.02); // measured 0.0095
    // Not trivially equal: the particles are really drawn (full differs from no smoke).
    float orange = -1.0f;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            orange = std::max(orange, full.at(x, y, 0) - full.at(x, y, 2));
    EXPECT_GT(orange, 0.2f);
}

} // namespace veil::test
