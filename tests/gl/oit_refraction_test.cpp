// OIT `phenomenological` with volume refraction ([Eisemann06] slice maps; phenomenological.h
// volumeRefraction) against analytic values: the per-pixel thickness of spheres and boxes,
// read back through glTF Beer-Lambert absorption (h = L ln(out / bkg) / ln c), the
// transmittance bkg * c^(d / L) of a thick absorbing box, the unchanged thin-surface model with
// the option off, and a larger refraction shift through a thick slab than through a thin one.
//
// All scenes: orthographic camera straight down from y = 10 (near 1, far 20: slice length
// 19 / 512 = 0.0371) over an 8 x 8 area at 128 x 128 pixels, no lights, ambient 0, black
// metallic glass (no reflection) of transmission 1 (only the medium absorbs).
#include "gl_fixture.h"

#include "base/error.h"
#include "frame/renderer.h"
#include "io/image_io.h"
#include "oit/phenomenological/phenomenological.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace veil::test {

namespace {

constexpr int kSize = 128;
constexpr double kPixelsPerUnit = 16.0;
constexpr double kSlice = 19.0 / 512.0;

double worldOf(int pixel) { return -4.0 + (pixel + 0.5) / kPixelsPerUnit; }

nlohmann::json baseScene(const std::vector<double>& background) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 128, "height": 128, "ambient": 0, "tonemap": "clamp"},
      "cameras": [{"name": "top", "type": "orthographic", "position": [0, 10, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 8, "near": 1,
                   "far": 20}],
      "materials": {}, "objects": []})");
    doc["render"]["background"] = background;
    return doc;
}

// Clear black metallic glass whose medium absorbs attenuationColor per distance L.
nlohmann::json glass(const std::vector<double>& attenuationColor, double distance, double ior = 1.0,
                     double transmission = 1.0) {
    return {{"base_color", 0.0},
            {"metalness", 1.0},
            {"roughness", 0.0},
            {"alpha", 1.0},
            {"transmission", transmission},
            {"ior", ior},
            {"attenuation_color", attenuationColor},
            {"attenuation_distance", distance}};
}

void addObject(nlohmann::json& doc, const nlohmann::json& shape, const std::string& material,
               const std::vector<double>& translate, double rotateZ = 0.0) {
    nlohmann::json object = {{"shape", shape}, {"material", material}};
    object["transform"] = {{"translate", translate}};
    if (rotateZ != 0.0) object["transform"]["rotate"] = {0.0, 0.0, rotateZ};
    doc["objects"].push_back(object);
}

nlohmann::json sphere(double r) {
    return {{"type", "sphere"}, {"radius", r}, {"segments", 128}, {"rings", 64}};
}

nlohmann::json box(double sx, double sy, double sz) {
    return {{"type", "box"}, {"size", {sx, sy, sz}}};
}

// Absorption of the red channel: c = 0.5 per L = 4 units, over a white background.
constexpr double kC = 0.5, kL = 4.0;

double thicknessFrom(const ImageF& img, int x, int y) {
    return kL * std::log(static_cast<double>(img.at(x, y, 0))) / std::log(kC);
}

} // namespace

class OitRefractionTest : public GlTest {
protected:
    static ImageF render(const nlohmann::json& doc, const std::string& technique,
                         const std::string& png) {
        const scene::Scene sc = scene::parseScene(doc, sourceDir());
        frame::Renderer renderer(sc, info(), {kSize, kSize, "", technique});
        renderer.render();
        io::writeImage(outputDir() / (png + ".png"), renderer.readLdr());
        return renderer.readHdr();
    }

    static nlohmann::json absorbingScene() {
        nlohmann::json doc = baseScene({1.0, 1.0, 1.0});
        doc["materials"]["glass"] = glass({kC, 0.7, 0.9}, kL);
        return doc;
    }
};

// [Eisemann06 sec. 3]: a sphere of radius r is 2 sqrt(r^2 - e^2) thick at distance e from its
// centre line, to within one slice (plus the tessellation's sag, < 0.002 here).
TEST_F(OitRefractionTest, SphereThicknessMatchesChord) {
    const double r = 2.0;
    nlohmann::json doc = absorbingScene();
    addObject(doc, sphere(r), "glass", {0, 0, 0});
    const ImageF img = render(doc, "phenomenological-volume", "refr_sphere_thickness");
    VEIL_EXPECT_NO_GL_ERROR();
    double maxErr = 0.0;
    int tested = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const double e2 = worldOf(x) * worldOf(x) + worldOf(y) * worldOf(y);
            if (e2 > 0.8 * 0.8 * r * r) continue; // the limb: tessellation dominates
            const double expected = 2.0 * std::sqrt(r * r - e2);
            maxErr = std::max(maxErr, std::abs(thicknessFrom(img, x, y) - expected));
            ++tested;
        }
    RecordProperty("max_thickness_error", std::to_string(maxErr));
    EXPECT_GT(tested, 1000);
    EXPECT_LE(maxErr, kSlice + 0.004);
    // Centre pixel and one at e = 1.53 (x = 88), singly.
    EXPECT_NEAR(thicknessFrom(img, 64, 64), 2.0 * r, kSlice + 0.004);
    const double e = worldOf(88), e2 = e * e + worldOf(64) * worldOf(64);
    EXPECT_NEAR(thicknessFrom(img, 88, 64), 2.0 * std::sqrt(r * r - e2), kSlice + 0.004);
    // Outside the sphere: no medium, the background unchanged.
    EXPECT_NEAR(img.at(4, 4, 0), 1.0, 1e-3);
}

// A box of depth d along the view axis is d thick; two disjoint spheres on the view axis add.
TEST_F(OitRefractionTest, BoxAndTwoSpheresThickness) {
    {
        nlohmann::json doc = absorbingScene();
        addObject(doc, box(4, 2.5, 4), "glass", {0, 0, 0});
        const ImageF img = render(doc, "phenomenological-volume", "refr_box_thickness");
        double maxErr = 0.0;
        for (int y = 40; y < 88; ++y)
            for (int x = 40; x < 88; ++x)
                maxErr = std::max(maxErr, std::abs(thicknessFrom(img, x, y) - 2.5));
        RecordProperty("box_max_thickness_error", std::to_string(maxErr));
        EXPECT_LE(maxErr, kSlice);
    }
    {
        nlohmann::json doc = absorbingScene();
        addObject(doc, sphere(1.0), "glass", {0, 2.5, 0});
        addObject(doc, sphere(1.5), "glass", {0, -2.0, 0});
        const ImageF img = render(doc, "phenomenological-volume", "refr_two_spheres");
        const double h = thicknessFrom(img, 64, 64);
        const double e2 = 2.0 * worldOf(64) * worldOf(64);
        const double expected = 2.0 * std::sqrt(1.0 - e2) + 2.0 * std::sqrt(2.25 - e2);
        RecordProperty("two_spheres_thickness", std::to_string(h));
        EXPECT_NEAR(h, expected, 2.0 * kSlice);
        // Only the big sphere at e = 1.2.
        const int x = 64 + static_cast<int>(1.2 * kPixelsPerUnit);
        const double e = worldOf(x), eb2 = e * e + worldOf(64) * worldOf(64);
        EXPECT_NEAR(thicknessFrom(img, x, 64), 2.0 * std::sqrt(2.25 - eb2), kSlice + 0.004);
    }
}

// glTF KHR_materials_volume through a thick box: out = bkg * c^(d / L) (d = 2, L = 4) per channel
// (2e-3 relative); with the option off the technique keeps its thin-surface model: out = bkg.
TEST_F(OitRefractionTest, BeerLambertThroughThickBox) {
    const std::vector<double> bkg{0.8, 0.9, 1.0}, c{0.5, 0.7, 0.9};
    const double d = 2.0, L = 4.0;
    nlohmann::json doc = baseScene(bkg);
    doc["materials"]["glass"] = glass(c, L);
    addObject(doc, box(4, d, 4), "glass", {0, 0, 0});
    const ImageF vol = render(doc, "phenomenological-volume", "refr_beer_lambert");
    const ImageF off = render(doc, "phenomenological", "refr_beer_lambert_off");
    VEIL_EXPECT_NO_GL_ERROR();
    double maxRel = 0.0, maxOff = 0.0;
    for (int y = 40; y < 88; ++y)
        for (int x = 40; x < 88; ++x)
            for (int k = 0; k < 3; ++k) {
                const double expected = bkg[k] * std::pow(c[k], d / L);
                maxRel = std::max(maxRel, std::abs(vol.at(x, y, k) - expected) / expected);
                maxOff = std::max(maxOff, std::abs(off.at(x, y, k) - bkg[k]));
            }
    RecordProperty("max_relative_error", std::to_string(maxRel));
    RecordProperty("off_max_abs_error", std::to_string(maxOff));
    EXPECT_LE(maxRel, 2e-3);
    EXPECT_LE(maxOff, 1e-3);
    // Outside the box both are the background.
    EXPECT_NEAR(vol.at(4, 4, 2), bkg[2], 1e-3);
}

// [McGuire16 Eq. 9] with Delta z := thickness: a bright bar on the floor seen through a tilted
// glass slab (ior 1.5, grey transmission 0.5 so it has net coverage) moves more through a 3-unit
// slab than through a 0.1-unit one of the same material.
TEST_F(OitRefractionTest, ThickSlabShiftsMoreThanThinPane) {
    auto barCentroid = [](const ImageF& img) {
        double sum = 0.0, weighted = 0.0;
        for (int y = 56; y < 72; ++y)
            for (int x = 24; x < 104; ++x) {
                const double v = img.at(x, y, 1);
                sum += v;
                weighted += v * x;
            }
        return weighted / std::max(sum, 1e-12);
    };
    auto scene = [](double thickness, bool withGlass) {
        nlohmann::json doc = baseScene({0.0, 0.0, 0.0});
        doc["materials"]["bar"] = {{"base_color", 0.0}, {"emission", {1.0, 1.0, 1.0}}};
        doc["materials"]["glass"] = glass({1.0, 1.0, 1.0}, 0.0, 1.5, 0.5);
        nlohmann::json bar = {{"type", "plane"}, {"size", {0.5, 8.0}}};
        addObject(doc, bar, "bar", {0, -4.0, 0});
        if (withGlass) addObject(doc, box(7, thickness, 7), "glass", {0, 0, 0}, 30.0);
        return doc;
    };
    const double bare = barCentroid(render(scene(0.1, false), "phenomenological", "refr_bar"));
    const ImageF thinImg = render(scene(0.1, true), "phenomenological-volume", "refr_thin_slab");
    const ImageF thickImg = render(scene(3.0, true), "phenomenological-volume", "refr_thick_slab");
    const double thin = barCentroid(thinImg) - bare, thick = barCentroid(thickImg) - bare;
    RecordProperty("shift_thin_px", std::to_string(thin));
    RecordProperty("shift_thick_px", std::to_string(thick));
    std::printf("bar shift: thin %.3f px, thick %.3f px\n", thin, thick);
    EXPECT_NEAR(bare, 64.0, 0.5);
    EXPECT_LT(std::abs(thin), 0.5);
    EXPECT_GT(std::abs(thick), std::abs(thin) + 1.5);
}

// The frame's fog emission draws in every geometry pass: in the slice-map pass it must leave
// no bits (oitEmit discards), in the accumulation it multiplies in as before. Homogeneous fog
// (sigma 0.2) over 13 units to an emissive floor: E exp(-2.6), and through the absorbing box
// additionally c^(d / L) (both products are exact in the technique's beta).
TEST_F(OitRefractionTest, FogWithVolumeRefraction) {
    nlohmann::json doc = baseScene({0.0, 0.0, 0.0});
    doc["render"]["fog_steps"] = 256;
    doc["render"]["fog_jitter"] = false;
    doc["materials"]["lamp"] = {{"base_color", 0.0}, {"emission", {2.0, 1.0, 0.5}}};
    doc["materials"]["glass"] = glass({0.5, 0.7, 0.9}, 4.0);
    addObject(doc, {{"type", "plane"}, {"size", {8.0, 8.0}}}, "lamp", {0, -4.0, 0});
    addObject(doc, box(4, 2, 4), "glass", {0, 0, 0});
    doc["volumes"] = {{{"procedural", "homogeneous"}, {"density_scale", 0.2}}};
    const ImageF img = render(doc, "phenomenological-volume", "refr_fog");
    VEIL_EXPECT_NO_GL_ERROR();
    const double T = std::exp(-0.2 * 13.0);
    EXPECT_NEAR(img.at(8, 8, 0), 2.0 * T, 0.01 * 2.0 * T);
    EXPECT_NEAR(img.at(64, 64, 0), 2.0 * T * std::sqrt(0.5), 0.01 * 2.0 * T);
    EXPECT_NEAR(img.at(64, 64, 2), 0.5 * T * std::pow(0.9, 0.5), 0.01 * 0.5 * T + 1e-3);
}

// Volume refraction with reduced-resolution particles (three geometry passes) on the smoke and
// glass scene: runs without GL errors, finite, and differs from the thin-surface image only
// where the glass is (the particles themselves have no volume).
TEST_F(OitRefractionTest, WithLowResolutionParticles) {
    const scene::Scene sc = scene::loadScene(sourceDir() / "datasets/scenes/oit-smoke-glass.json");
    auto renderWith = [&](bool volume) {
        oit::PhenomenologicalParams p;
        p.particleDownsample = 2;
        p.volumeRefraction = volume;
        frame::Renderer renderer(sc, info(),
                                 {160, 90, "", "phenomenological", oit::toProperties(p)});
        renderer.render();
        io::writeImage(outputDir() /
                           (volume ? "refr_smoke_glass_volume.png" : "refr_smoke_glass_thin.png"),
                       renderer.readLdr());
        return renderer.readHdr();
    };
    const ImageF thin = renderWith(false), vol = renderWith(true);
    VEIL_EXPECT_NO_GL_ERROR();
    double diff = 0.0;
    for (std::size_t i = 0; i < vol.pixels.size(); ++i) {
        ASSERT_TRUE(std::isfinite(vol.pixels[i]));
        diff = std::max(diff, std::abs(static_cast<double>(vol.pixels[i] - thin.pixels[i])));
    }
    RecordProperty("max_abs_difference", std::to_string(diff));
    EXPECT_GT(diff, 1e-3); // the glass ball is a volume now
}

// Bad parameters end in veil::Error.
TEST_F(OitRefractionTest, RejectsBadVolumeParameters) {
    oit::PhenomenologicalParams p;
    p.volumeRefraction = true;
    p.thicknessReference = -1.0f;
    EXPECT_THROW(p.validate(), Error);
    p.thicknessReference = 0.0f;
    p.volumeBlur = std::nanf("");
    EXPECT_THROW(p.validate(), Error);
}

// A glass sphere (r = 2.5, ior 1.4, transmission 0.9, roughness 0.3) with blue-green
// absorption c = (0.2, 0.6, 0.9) per L = 1.5, as a thin shell (`phenomenological`) and as a
// volume (`phenomenological-volume`), over a striped floor and over a uniform one. Checked:
//  - thin shell, striped floor: the centre looks through the gap between two stripes (the
//    0.05 grey background) and two interfaces of transmission 0.9 each ([McGuire16 Eq. 2] with
//    alpha 1: m = T), so it is 0.05 * 0.9^2 in every channel: the shell ignores the medium;
//    and the volume image differs from it;
//  - uniform floor: thin and volume look at the same uniform floor through the same two
//    interfaces, so vol / thin is the medium's transmittance alone, Beer-Lambert
//    c^(h / L) with h the straight chord 2 sqrt(r^2 - e^2) that the slice map measures along
//    the view column [Eisemann06], within the thickness error of SphereThicknessMatchesChord
//    (one slice plus tessellation sag: kSlice + 0.004), i.e. relative |ln c| (kSlice + 0.004)
//    / L, plus 1e-3 for RGBA16F; at the centre (e = 0.03) h = 2r; for e up to 0.6 r;
//  - the limb is lighter than the centre: vol / thin rises with e out to 0.8 r.
// Mutation tried: a 5% longer attenuation distance in phenomenological/emit.glsl
// (h / (1.05 L)) fails 9 of the Beer-Lambert checks; the old check (centre darker than 0.8
// times the thin shell) passed it.
TEST_F(OitRefractionTest, ThickVersusThinSphereImages) {
    const std::vector<double> c{0.2, 0.6, 0.9};
    const double r = 2.5, L = 1.5, T = 0.9;
    auto scene = [&](bool uniformFloor) {
        nlohmann::json doc = baseScene({0.05, 0.05, 0.05});
        for (int i = 0; i < 8; ++i) {
            const std::string name = fmt::format("stripe{}", i);
            const bool odd = uniformFloor || i % 2;
            doc["materials"][name] = {{"base_color", 0.0},
                                      {"emission", {odd ? 1.0 : 0.2, 0.9, odd ? 0.3 : 1.0}}};
            addObject(doc, {{"type", "plane"}, {"size", {uniformFloor ? 1.0 : 0.5, 8.0}}}, name,
                      {-3.5 + i * 1.0, -4.0, 0.0});
        }
        nlohmann::json m = glass(c, L, 1.4, T);
        m["roughness"] = 0.3;
        doc["materials"]["glass"] = m;
        addObject(doc, sphere(r), "glass", {0, 0, 0});
        return doc;
    };
    const ImageF thin = render(scene(false), "phenomenological", "refr_sphere_thin_shell");
    const ImageF vol = render(scene(false), "phenomenological-volume", "refr_sphere_volume");
    VEIL_EXPECT_NO_GL_ERROR();
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(thin.at(64, 64, k), 0.05 * T * T, 1e-3 * 0.05) << "channel " << k;
    EXPECT_GT(compareImages(thin, vol).maxAbs, 0.02);

    const ImageF thinU = render(scene(true), "phenomenological", "refr_sphere_thin_uniform");
    const ImageF volU = render(scene(true), "phenomenological-volume", "refr_sphere_vol_uniform");
    VEIL_EXPECT_NO_GL_ERROR();
    for (int k = 0; k < 3; ++k) {
        const double tol = std::abs(std::log(c[k])) * (kSlice + 0.004) / L + 1e-3;
        double prev = 0.0;
        for (int x : {64, 72, 80, 88, 96}) { // e = 0.03 .. 2.03 (0.81 r)
            const double ratio = volU.at(x, 64, k) / thinU.at(x, 64, k);
            const double e2 = worldOf(x) * worldOf(x) + worldOf(64) * worldOf(64);
            const double expected = std::pow(c[k], 2.0 * std::sqrt(r * r - e2) / L);
            std::printf("sphere ch%d x %d: vol / thin %.5f, Beer-Lambert %.5f (rel. tol %.4f)\n", k,
                        x, ratio, expected, tol);
            if (e2 <= 0.6 * 0.6 * r * r) {
                EXPECT_NEAR(ratio, expected, tol * expected) << "channel " << k << " x " << x;
            }
            EXPECT_GT(ratio, prev) << "channel " << k << " x " << x << ": limb not lighter";
            prev = ratio;
        }
    }
}

} // namespace veil::test
