// Stochastic transparency on the GL [Enderton11]: the paper's Examples 1 and 2 (exact values and
// the RMS errors it states for S = 4), determinism per seed, colored transmission, and each variant
// against an exact sorted composite of the same planes computed here on the CPU in double
// precision. Every pixel of a full-frame plane stack is an independent trial (the mask hash
// includes the pixel), so one 64x64 frame gives 4096 samples of the estimator.
#include "gl_fixture.h"

#include "oit/cpu/composite.h"

#include "base/error.h"
#include "frame/renderer.h"
#include "io/image_io.h"
#include "oit/cpu/stochastic.h"
#include "oit/stochastic/stochastic.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>

namespace veil::test {

class OitStochasticGLTest : public GlTest {
public:
    static const gpu::ContextInfo& ctx() { return info(); }
};

namespace {

constexpr int kSize = 64;
constexpr double kView = 2.0; // ortho_height: pixel size 1/32 world units

struct Plane {
    double height; // y, camera looks down from y = 10
    std::array<double, 3> emission;
    double alpha;
    std::array<double, 3> transmission{0, 0, 0};
    double x0 = -4, x1 = 4, z0 = -4, z1 = 4; // extent in world x, z
};

nlohmann::json sceneJson(const std::vector<Plane>& planes, std::array<double, 3> background,
                         std::uint32_t seed) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"ambient": 0, "tonemap": "clamp"},
      "cameras": [{"name": "top", "type": "orthographic", "position": [0, 10, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 2, "near": 1,
                   "far": 20}]})");
    doc["render"]["background"] = background;
    doc["render"]["seed"] = seed;
    doc["materials"] = nlohmann::json::object();
    doc["objects"] = nlohmann::json::array();
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const Plane& p = planes[i];
        const std::string m = fmt::format("m{}", i);
        doc["materials"][m] = {{"base_color", 0},
                               {"emission", p.emission},
                               {"alpha", p.alpha},
                               {"transmission", p.transmission}};
        doc["objects"].push_back(
            {{"shape", {{"type", "plane"}, {"size", {p.x1 - p.x0, p.z1 - p.z0}}}},
             {"material", m},
             {"transform", {{"translate", {(p.x0 + p.x1) / 2, p.height, (p.z0 + p.z1) / 2}}}}});
    }
    return doc;
}

ImageF render(const std::vector<Plane>& planes, std::array<double, 3> background,
              const std::string& technique, std::uint32_t seed, int samples, int passes) {
    const scene::Scene sc = scene::parseScene(sceneJson(planes, background, seed), sourceDir());
    frame::Renderer renderer(
        sc, OitStochasticGLTest::ctx(),
        {kSize, kSize, "", technique, {{"samples", samples}, {"passes", passes}}});
    renderer.render();
    ImageF img = renderer.readHdr();
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    return img;
}

// Exact sorted composite (src/oit/cpu/composite.h) at each pixel centre; nearer planes are
// higher (the camera looks down).
ImageF sortedComposite(const std::vector<Plane>& planes, std::array<double, 3> background) {
    ImageF out(kSize, kSize, 4);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const double wx = (x + 0.5) / kSize * kView - kView / 2;
            const double wz = (y + 0.5) / kSize * kView - kView / 2; // row 0 = -z (up = -z)
            std::vector<oit::cpu::Fragment> frags;
            for (const Plane& p : planes)
                if (wx >= p.x0 && wx <= p.x1 && wz >= p.z0 && wz <= p.z1)
                    frags.push_back(oit::cpu::makeFragment(
                        -p.height, glm::dvec3(p.emission[0], p.emission[1], p.emission[2]), p.alpha,
                        glm::dvec3(p.transmission[0], p.transmission[1], p.transmission[2])));
            const glm::dvec3 c = oit::cpu::compositeSorted(
                frags, glm::dvec3(background[0], background[1], background[2]));
            for (int k = 0; k < 3; ++k)
                out.at(x, y, k) = static_cast<float>(c[k]);
            out.at(x, y, 3) = 1.0f;
        }
    return out;
}

struct PixelStats {
    std::array<double, 3> mean{0, 0, 0}, rms{0, 0, 0};
    int count = 0;
};

// Mean and RMS error against `exact` over all pixels of all images.
PixelStats stats(const std::vector<ImageF>& images, const double exact[3]) {
    PixelStats s;
    for (const ImageF& img : images)
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                for (int k = 0; k < 3; ++k) {
                    const double v = img.at(x, y, k);
                    s.mean[k] += v;
                    s.rms[k] += (v - exact[k]) * (v - exact[k]);
                }
                ++s.count;
            }
    for (int k = 0; k < 3; ++k) {
        s.mean[k] /= s.count;
        s.rms[k] = std::sqrt(s.rms[k] / s.count);
    }
    return s;
}

void savePng(const std::string& name, const ImageF& img) {
    io::writeImage(outputDir() / (name + ".png"), img);
}

const char* const kVariants[] = {"stochastic", "stochastic-alpha", "stochastic-depth"};

oit::cpu::StochasticVariant cpuVariant(const std::string& technique) {
    if (technique == "stochastic-alpha") return oit::cpu::StochasticVariant::AlphaCorrected;
    if (technique == "stochastic-depth") return oit::cpu::StochasticVariant::DepthBased;
    return oit::cpu::StochasticVariant::Basic;
}

// [Enderton11 Example 1]: red over green (alpha 0.45 each) over blue.
std::vector<Plane> example1() { return {{3, {1, 0, 0}, 0.45}, {2, {0, 1, 0}, 0.45}}; }
// [Enderton11 Example 2]: four white planes of alpha 1/4 over 25 percent grey.
std::vector<Plane> example2() {
    return {{4, {1, 1, 1}, 0.25}, {3, {1, 1, 1}, 0.25}, {2, {1, 1, 1}, 0.25}, {1, {1, 1, 1}, 0.25}};
}

// The per-pixel distribution of the three estimators, written from [Enderton11] (not from the
// shader or src/oit/cpu/stochastic): layer i (front to back, coverage a_i, colour c_i) covers R_i =
// floor(a_i S + xi) of the S samples, xi uniform, so R_i = floor(a_i S) + 1 with probability
// frac(a_i S) and floor(a_i S) otherwise, through a mask drawn uniformly from the C(S, R_i) masks
// of R_i bits, independently per layer (3.1). A sample shows the nearest layer covering it. With A
// = 1 - prod(1 - a_i) the exact total alpha:
//   basic (3.1):            mean over samples of the colour shown (background if none);
//   alpha-corrected (3.3):  A * (mean colour of the covered samples) + (1 - A) bg, and
//                           (1 - A) bg when no sample is covered (4.1 "otherwise 0");
//   depth-based (3.4, 3.5): vis_i = fraction of samples no nearer layer covers;
//                           A * sum(a_i vis_i c_i) / sum(a_i vis_i) + (1 - A) bg.
// Enumerating all (R_i, mask_i) gives each estimator's exact mean, variance and fourth
// central moment per pixel (the basic one's mean is the exact composite: unbiased).
struct PixelMoments {
    std::array<double, 3> mean{0, 0, 0}, var{0, 0, 0}, m4{0, 0, 0};
};

PixelMoments estimatorMoments(const std::vector<Plane>& front2back,
                              std::array<double, 3> background, int S,
                              const std::string& technique) {
    struct Outcome {
        std::uint32_t mask;
        double p;
    };
    std::vector<std::vector<Outcome>> perLayer;
    for (const Plane& l : front2back) {
        const double x = l.alpha * S;
        const int r0 = static_cast<int>(std::floor(x));
        const double f = x - r0;
        std::vector<Outcome> o;
        for (int r : {r0, r0 + 1}) {
            const double pr = r == r0 ? 1.0 - f : f;
            if (pr <= 0.0 || r > S) continue;
            std::vector<std::uint32_t> masks;
            for (std::uint32_t m = 0; m < (1u << S); ++m)
                if (std::popcount(m) == r) masks.push_back(m);
            for (std::uint32_t m : masks)
                o.push_back({m, pr / masks.size()});
        }
        perLayer.push_back(o);
    }
    std::vector<std::pair<std::array<double, 3>, double>> values; // (pixel value, probability)
    std::vector<std::size_t> idx(perLayer.size(), 0);
    while (true) {
        double p = 1.0, total = 1.0;
        for (const Plane& l : front2back)
            total *= 1.0 - l.alpha;
        const double A = 1.0 - total;
        std::array<double, 3> v{0, 0, 0}, covered{0, 0, 0};
        int nCovered = 0;
        for (int k = 0; k < S; ++k) {
            std::array<double, 3> c = background;
            bool hit = false;
            for (std::size_t i = 0; i < perLayer.size() && !hit; ++i)
                if (perLayer[i][idx[i]].mask & (1u << k)) {
                    c = front2back[i].emission;
                    hit = true;
                }
            nCovered += hit;
            for (int ch = 0; ch < 3; ++ch) {
                v[ch] += c[ch] / S;
                if (hit) covered[ch] += c[ch];
            }
        }
        if (technique == "stochastic-alpha") {
            for (int ch = 0; ch < 3; ++ch)
                v[ch] = (nCovered ? A * covered[ch] / nCovered : 0.0) + total * background[ch];
        } else if (technique == "stochastic-depth") {
            std::array<double, 3> num{0, 0, 0};
            double den = 0.0;
            std::uint32_t nearer = 0; // samples covered by the layers in front
            for (std::size_t i = 0; i < perLayer.size(); ++i) {
                const double vis = double(S - std::popcount(nearer)) / S;
                den += front2back[i].alpha * vis;
                for (int ch = 0; ch < 3; ++ch)
                    num[ch] += front2back[i].alpha * vis * front2back[i].emission[ch];
                nearer |= perLayer[i][idx[i]].mask;
            }
            for (int ch = 0; ch < 3; ++ch)
                v[ch] = (den > 0.0 ? A * num[ch] / den : 0.0) + total * background[ch];
        }
        for (std::size_t i = 0; i < perLayer.size(); ++i)
            p *= perLayer[i][idx[i]].p;
        values.push_back({v, p});
        std::size_t i = 0;
        while (i < idx.size() && ++idx[i] == perLayer[i].size())
            idx[i++] = 0;
        if (i == idx.size()) break;
    }
    PixelMoments m;
    for (const auto& [v, p] : values)
        for (int ch = 0; ch < 3; ++ch)
            m.mean[ch] += p * v[ch];
    for (const auto& [v, p] : values)
        for (int ch = 0; ch < 3; ++ch) {
            const double d = v[ch] - m.mean[ch];
            m.var[ch] += p * d * d;
            m.m4[ch] += p * d * d * d * d;
        }
    return m;
}

// Checks one variant on one example over `seeds` frames: the mean over seeds and pixels
// against the expected mean of the mask model (S = 4, one pass) or of the simulator (more
// samples: too many masks to enumerate) (the exact value for the unbiased basic method, the
// biased E(A), E(D) of [Enderton11 sec. 4] otherwise) and the RMS against the simulator's RMS and
// the value the paper states (where `paper` is given, S = 4 only).
void checkExample(const std::string& name, const std::vector<Plane>& planes,
                  std::array<double, 3> background, const std::string& technique, int passes,
                  const double* paper, int requestedSamples = 4) {
    const int samples = oit::stochasticEffectiveSamples(requestedSamples);
    ASSERT_EQ(samples, requestedSamples) << "the driver has fewer MSAA samples";
    std::vector<ImageF> images;
    for (std::uint32_t seed = 1; seed <= 3; ++seed)
        images.push_back(render(planes, background, technique, seed, samples, passes));
    savePng(fmt::format("oit_stochastic_{}_{}_s{}_x{}", name, technique, samples, passes),
            images[0]);

    std::vector<oit::cpu::StochasticFragment> frags;
    for (const Plane& p : planes)
        frags.push_back({{p.emission[0], p.emission[1], p.emission[2]}, p.alpha});
    const double bg[3] = {background[0], background[1], background[2]};
    auto sim = oit::cpu::simulateStochasticPixel(frags, bg, cpuVariant(technique), samples, passes,
                                                 40000, 11);
    if (samples == 4 && passes == 1) {
        // Small enough to enumerate: the expected mean and RMS from the [Enderton11] mask model
        // (estimatorMoments), not from the simulator that mirrors the shader's hash.
        const PixelMoments model = estimatorMoments(planes, background, samples, technique);
        for (int k = 0; k < 3; ++k) {
            sim.mean[k] = model.mean[k];
            sim.rms[k] = std::sqrt(model.var[k] +
                                   (model.mean[k] - sim.exact[k]) * (model.mean[k] - sim.exact[k]));
        }
    }
    const PixelStats s = stats(images, sim.exact);
    const double n = s.count;
    for (int k = 0; k < 3; ++k) {
        SCOPED_TRACE(fmt::format("{} {} x{} channel {}: mean {:.4f} (sim {:.4f}, exact {:.4f}), "
                                 "rms {:.4f} (sim {:.4f}, paper {})",
                                 name, technique, passes, k, s.mean[k], sim.mean[k], sim.exact[k],
                                 s.rms[k], sim.rms[k], paper ? paper[k] : -1.0));
        std::printf("[stoch] %s %s S=%d x%d ch%d mean %.4f exact %.4f sim-mean %.4f rms %.4f "
                    "sim-rms %.4f paper %.2f\n",
                    name.c_str(), technique.c_str(), samples, passes, k, s.mean[k], sim.exact[k],
                    sim.mean[k], s.rms[k], sim.rms[k], paper ? paper[k] : -1.0);
        // Mean: 5 standard errors of both estimates plus RGBA16F rounding.
        const double se = 5.0 * sim.rms[k] * (1.0 / std::sqrt(n) + 1.0 / std::sqrt(40000.0));
        EXPECT_NEAR(s.mean[k], sim.mean[k], se + 2e-3);
        if (technique == "stochastic") {
            EXPECT_NEAR(s.mean[k], sim.exact[k], se + 2e-3);
        }
        // RMS: within 10 percent of the expected estimator RMS (model or simulator).
        EXPECT_NEAR(s.rms[k], sim.rms[k], 0.1 * sim.rms[k] + 3e-3);
        if (paper) {
            EXPECT_LE(s.rms[k],
                      paper[k] + 0.01); // [Enderton11 sec. 3.1-3.4], rounded to hundredths
        }
    }
}

} // namespace

TEST_F(OitStochasticGLTest, Example1AtFourSamplesMatchesPaper) {
    // [Enderton11 sec. 3.1]: stratified (0.10, 0.17, 0.18); 3.3 alpha-corrected (0.17, 0.14, 0.0);
    // 3.4 depth-based with alpha correction (0.14, 0.12, 0.0).
    const double basic[3] = {0.10, 0.17, 0.18}, alpha[3] = {0.17, 0.14, 0.0},
                 depth[3] = {0.14, 0.12, 0.0};
    checkExample("ex1", example1(), {0, 0, 1}, "stochastic", 1, basic);
    checkExample("ex1", example1(), {0, 0, 1}, "stochastic-alpha", 1, alpha);
    checkExample("ex1", example1(), {0, 0, 1}, "stochastic-depth", 1, depth);
}

TEST_F(OitStochasticGLTest, Example2AtFourSamplesMatchesPaper) {
    // [Enderton11]: basic stratified 0.12; alpha correction and depth-based with correction 0.0.
    const double basic[3] = {0.12, 0.12, 0.12}, zero[3] = {0, 0, 0};
    checkExample("ex2", example2(), {0.25, 0.25, 0.25}, "stochastic", 1, basic);
    checkExample("ex2", example2(), {0.25, 0.25, 0.25}, "stochastic-alpha", 1, zero);
    checkExample("ex2", example2(), {0.25, 0.25, 0.25}, "stochastic-depth", 1, zero);
}

TEST_F(OitStochasticGLTest, RepeatedPassesGiveSixteenSamples) {
    // llvmpipe has 4x MSAA: 4 passes with one 16-bit stratified mask split across them
    // [Enderton11 footnote 3] give S = 16; the error must follow the 16-sample simulation.
    for (const char* t : kVariants)
        checkExample("ex1", example1(), {0, 0, 1}, t, 4, nullptr);
}

TEST_F(OitStochasticGLTest, SameSeedIsBitIdenticalDifferentSeedsDiffer) {
    for (const char* t : kVariants) {
        const ImageF a = render(example1(), {0, 0, 1}, t, 7, 4, 2);
        const ImageF b = render(example1(), {0, 0, 1}, t, 7, 4, 2);
        const ImageF c = render(example1(), {0, 0, 1}, t, 8, 4, 2);
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)), 0)
            << t;
        EXPECT_GT(compareImages(a, c).rmse, 0.01) << t << ": seeds 7 and 8 gave the same image";
    }
}

TEST_F(OitStochasticGLTest, ColoredTransmissionOfOneLayerIsExactWithCorrection) {
    // One layer: alpha correction makes A and D exact [Enderton11 sec. 3.3]; the background is
    // dimmed by the exact per-channel (1 - a + aT) [McGuire16 Eq. 2]. a_eff = 0.6 (1 - 0.5) = 0.3.
    const std::vector<Plane> planes = {{2, {0.2, 0.5, 0.1}, 0.6, {0.9, 0.1, 0.5}}};
    const ImageF ref = sortedComposite(planes, {1, 0.8, 0.6});
    for (const char* t : {"stochastic-alpha", "stochastic-depth"}) {
        const ImageF img = render(planes, {1, 0.8, 0.6}, t, 1, 4, 1);
        const ImageDiff d = compareImages(img, ref);
        EXPECT_LT(d.maxAbs, 2e-3) << t;
    }
}

TEST_F(OitStochasticGLTest, VariantsAgainstSortedComposite) {
    // Overlapping planes (1 to 4 layers), one with colored transmission, and an opaque plane
    // hiding the lower layers in the left quarter: depth test against the opaque depth.
    const std::vector<Plane> planes = {
        {4.0, {0.9, 0.2, 0.1}, 0.5, {0, 0, 0}, -1, 0.5, -1, 1},
        {3.0, {0.1, 0.8, 0.3}, 0.35, {0, 0, 0}, -0.5, 1, -1, 0.5},
        {2.0, {0.2, 0.3, 0.9}, 0.6, {0.3, 0.6, 0.9}, -1, 1, -0.25, 1},
        {1.0, {0.9, 0.9, 0.2}, 0.7, {0, 0, 0}, -0.75, 0.75, -0.75, 0.75},
        {2.5, {0.4, 0.4, 0.4}, 1.0, {0, 0, 0}, -1, -0.5, -1, 1}, // opaque
    };
    const std::array<double, 3> bg{0.05, 0.05, 0.1};
    const ImageF ref = sortedComposite(planes, bg);
    savePng("oit_stochastic_sorted_reference", ref);
    double rmse[3][2];
    for (int v = 0; v < 3; ++v)
        for (int p = 0; p < 2; ++p) {
            const int passes = p == 0 ? 1 : 4;
            const ImageF img = render(planes, bg, kVariants[v], 3, 4, passes);
            savePng(fmt::format("oit_stochastic_planes_{}_x{}", kVariants[v], passes), img);
            const ImageDiff d = compareImages(img, ref);
            rmse[v][p] = d.rmse;
            std::printf("[stoch] planes %s S=4 x%d (total %d samples): RMSE %.4f max %.4f\n",
                        kVariants[v], passes, 4 * passes, d.rmse, d.maxAbs);
            if (d.rmse > (p == 0 ? 0.15 : 0.07)) writeFailureImages(kVariants[v], img, ref);
        }
    // Bounds: about 1.3x the values measured on llvmpipe (0.118, 0.103, 0.031 at 4 samples;
    // 0.055, 0.047, 0.021 at 16). The depth-based floor comes from the colored-transmission
    // plane: layers behind it are dimmed by the grey a_eff visibility, not per channel.
    EXPECT_LT(rmse[0][0], 0.15);
    EXPECT_LT(rmse[1][0], 0.13);
    EXPECT_LT(rmse[2][0], 0.045);
    EXPECT_LT(rmse[0][1], 0.07);
    EXPECT_LT(rmse[1][1], 0.062);
    EXPECT_LT(rmse[2][1], 0.03);
    for (int v = 0; v < 3; ++v)
        EXPECT_LT(rmse[v][1], rmse[v][0]) << kVariants[v];
    EXPECT_LT(rmse[2][0], rmse[0][0]); // depth-based beats basic [Enderton11 Fig. 4]
}

TEST_F(OitStochasticGLTest, EstimatorsMatchTheMaskModelStatistically) {
    // Mitsuba-style statistical test of the three variants (4 samples, one pass) against the
    // exact sorted composite (src/oit/cpu/composite.h) and the [Enderton11] mask model above:
    // overlapping planes make regions of 1..4 layers. Per region (the pixels whose 3 x 3
    // neighbourhood has the same plane set, so no MSAA sample straddles an edge), over 32 seeds:
    //  - mean: within 4 standard errors of the model's mean, which for the basic estimator is
    //    the exact composite (unbiased, [Enderton11 sec. 3.1]; asserted) and for the corrected ones
    //    their expected values E(A), E(D) (biased, [Enderton11 sec. 4.1]); the standard error is
    //    sqrt(var / n) with var from the enumeration (pixels and seeds independent, as the
    //    per-pixel, per-seed mask hash is meant to make them), plus 2e-3 for RGBA16F;
    //  - variance: the sample variance within 4 of its standard errors sqrt((mu4 - var^2) / n)
    //    of the model's variance, plus 2e-4 (a hash that correlates masks across layers,
    //    pixels or seeds changes the spread even when the mean survives).
    // Opaque-free and T = 0 (the basic variant models colored T only through its average).
    // Mutations tried on emit.glsl: xi = hash >> 9 instead of >> 8 (xi in [0, 0.5): R biased
    // low) fails all three variants by 54-63 SE; the pixel row left out of the seed (masks
    // shared along columns) by 5-11 SE. Changing the PCG constants (747796405 -> 747796407,
    // 747796404 or 1, 2891336453 -> 0, 277803737 -> 277803736, output shift 22 -> 16) gives a
    // different but equally random hash: it passes here (basic: worst 2-3.6 SE), as it should; only
    // the goldens (bit for bit) see it.
    const std::vector<Plane> planes = {
        {4.0, {0.9, 0.2, 0.1}, 0.5, {0, 0, 0}, -1, 0.5, -1, 1},
        {3.0, {0.1, 0.8, 0.3}, 0.35, {0, 0, 0}, -0.5, 1, -1, 0.5},
        {2.0, {0.2, 0.3, 0.9}, 0.6, {0, 0, 0}, -1, 1, -0.25, 1},
        {1.0, {0.9, 0.9, 0.2}, 0.7, {0, 0, 0}, -0.75, 0.75, -0.75, 0.75},
    };
    const std::array<double, 3> bg{0.05, 0.05, 0.1};
    const ImageF exact = sortedComposite(planes, bg);
    auto key = [&](int x, int y) {
        const double wx = (x + 0.5) / kSize * kView - kView / 2;
        const double wz = (y + 0.5) / kSize * kView - kView / 2;
        int k = 0;
        for (std::size_t i = 0; i < planes.size(); ++i)
            if (wx >= planes[i].x0 && wx <= planes[i].x1 && wz >= planes[i].z0 &&
                wz <= planes[i].z1)
                k |= 1 << i;
        return k;
    };
    constexpr int kSeeds = 32;
    for (const std::string technique : kVariants) {
        SCOPED_TRACE(technique);
        std::vector<ImageF> images;
        for (std::uint32_t seed = 1; seed <= kSeeds; ++seed)
            images.push_back(render(planes, bg, technique, seed * 7919u, 4, 1));
        struct Region {
            double sum[3] = {0, 0, 0}, sumSq[3] = {0, 0, 0}, exact[3] = {0, 0, 0};
            double n = 0;
        };
        std::map<int, Region> regions;
        for (int y = 1; y + 1 < kSize; ++y)
            for (int x = 1; x + 1 < kSize; ++x) {
                const int k = key(x, y);
                bool interior = true;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        interior = interior && key(x + dx, y + dy) == k;
                if (!interior) continue;
                Region& r = regions[k];
                for (int c = 0; c < 3; ++c)
                    r.exact[c] = exact.at(x, y, c);
                for (const ImageF& img : images) {
                    for (int c = 0; c < 3; ++c) {
                        r.sum[c] += img.at(x, y, c);
                        r.sumSq[c] += double(img.at(x, y, c)) * img.at(x, y, c);
                    }
                    r.n += 1;
                }
            }
        ASSERT_GE(regions.size(), 8u);
        double worstMean = 0.0, worstVar = 0.0;
        for (const auto& [k, r] : regions) {
            std::vector<Plane> layers; // front to back: higher planes are nearer
            for (std::size_t i = 0; i < planes.size(); ++i)
                if (k & (1 << i)) layers.push_back(planes[i]);
            std::sort(layers.begin(), layers.end(),
                      [](const Plane& a, const Plane& b) { return a.height > b.height; });
            const PixelMoments model = estimatorMoments(layers, bg, 4, technique);
            for (int c = 0; c < 3; ++c) {
                // The basic estimator's mean is the exact composite (unbiased), independently.
                if (technique == "stochastic") {
                    ASSERT_NEAR(model.mean[c], r.exact[c], 1e-5) << k;
                }
                const double mean = r.sum[c] / r.n;
                const double var = r.sumSq[c] / r.n - mean * mean;
                const double seMean = std::sqrt(model.var[c] / r.n);
                const double seVar =
                    std::sqrt(std::max(model.m4[c] - model.var[c] * model.var[c], 0.0) / r.n);
                std::printf(
                    "[stoch] %s region %2d (%4.0f samples) ch%d: mean %.4f model %.4f (%.2f SE), "
                    "var %.5f model %.5f (%.2f SE)\n",
                    technique.c_str(), k, r.n, c, mean, model.mean[c],
                    (mean - model.mean[c]) / std::max(seMean, 1e-12), var, model.var[c],
                    (var - model.var[c]) / std::max(seVar, 1e-12));
                EXPECT_NEAR(mean, model.mean[c], 4.0 * seMean + 2e-3)
                    << "region " << k << " ch " << c;
                EXPECT_NEAR(var, model.var[c], 4.0 * seVar + 2e-4) << "region " << k << " ch " << c;
                if (seMean > 1e-9)
                    worstMean = std::max(worstMean, std::abs(mean - model.mean[c]) / seMean);
                if (seVar > 1e-9)
                    worstVar = std::max(worstVar, std::abs(var - model.var[c]) / seVar);
            }
        }
        std::printf("[stoch] %s: worst |mean - model| %.2f SE, worst |var - model| %.2f SE\n",
                    technique.c_str(), worstMean, worstVar);
    }
}

TEST_F(OitStochasticGLTest, EightSamplesWhereTheDriverHasThem) {
    // [Enderton11 sec. 3.5] uses 8x MSAA; llvmpipe has 4, NVIDIA GPUs 8 and more.
    if (oit::stochasticEffectiveSamples(8) < 8) GTEST_SKIP() << "driver has fewer than 8 samples";
    for (const char* t : kVariants) {
        checkExample("ex1", example1(), {0, 0, 1}, t, 1, nullptr, 8);
        checkExample("ex2", example2(), {0.25, 0.25, 0.25}, t, 1, nullptr, 8);
    }
}

TEST_F(OitStochasticGLTest, OpaqueDepthCopiedOnlyWhereAPassWroteDepth) {
    // The MSAA copy of the opaque depth is redrawn only before a pass that needs it
    // and finds depth written since the last copy: pass 0 and every stochastic pass but the
    // first after the total-alpha pass, i.e. P copies per frame for P passes (1 + P before:
    // the total-alpha pass writes no depth). Counted by the technique (stats "depth_copies")
    // and held to the count derived here from the pass list of [Enderton11 sec. 3.5]; the images of
    // the opaque-occluder test above (VariantsAgainstSortedComposite, passes 1 and 4) show that the
    // skipped copies were redundant.
    const std::vector<Plane> planes = {{2, {0.2, 0.5, 0.1}, 0.6},
                                       {1.5, {0.4, 0.4, 0.4}, 1.0, {0, 0, 0}, -1, 0, -1, 1}};
    for (const char* t : kVariants)
        for (int passes : {1, 3}) {
            const scene::Scene sc = scene::parseScene(sceneJson(planes, {0, 0, 1}, 5), sourceDir());
            frame::Renderer renderer(sc, ctx(),
                                     {kSize, kSize, "", t, {{"samples", 4}, {"passes", passes}}});
            renderer.render();
            renderer.render(); // per frame, not accumulated over frames
            const nlohmann::json st = renderer.technique().stats();
            EXPECT_EQ(st.at("depth_copies").get<int>(), passes) << t << " x" << passes;
            EXPECT_EQ(st.at("geometry_passes").get<int>(),
                      std::string(t) == "stochastic-depth" ? 1 + 2 * passes
                      : std::string(t) == "stochastic"     ? passes
                                                           : 1 + passes)
                << t;
        }
}

TEST_F(OitStochasticGLTest, BadParametersAreErrors) {
    const auto& registry = oit::Registry::instance();
    EXPECT_THROW(registry.resolve("stochastic", {{"samples", 0}}, "t"), veil::Error);
    EXPECT_THROW(registry.resolve("stochastic", {{"passes", 0}}, "t"), veil::Error);
    EXPECT_THROW(registry.resolve("stochastic-depth", {{"sample", 4}}, "t"), veil::Error);
    EXPECT_EQ(oit::stochasticEffectiveSamples(64), std::min(info().maxSamples, 32));
}

} // namespace veil::test
