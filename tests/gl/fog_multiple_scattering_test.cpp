// Multiple scattering of the fog marcher by octaves [Wrenninge13, Hillaire16] against the
// double-precision path tracer (src/integrators/path_tracer.h, itself checked against the
// adding-doubling slab in tests/unit/path_tracer_test.cpp) on a cloud-like slab: albedo 0.99,
// Henyey-Greenstein g 0.6, optical thickness 4, a sun at normal incidence, no sky. The
// octaves are an approximation: the tolerance is the error measured for the defaults (see
// the numbers below) plus the reference's noise, and single scattering (1 octave) must be
// outside it, so that the test fails when the octaves do nothing or too much.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "grid/density_grid.h"
#include "integrators/path_tracer.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>

namespace veil::test {

namespace {

// The multiple-scattering settings of datasets/scenes/cloud-wdas.json (a = c = 0.5, the
// defaults), tuned against the path tracer on that cloud (docs/volumes.md).
constexpr int kCloudOctaves = 8;
constexpr double kCloudScattering = 0.7; // b
// (octaves - path tracer) / path tracer as this test measures it (llvmpipe, 32 samples per
// pixel): reflection -0.158, transmission -0.251; single scattering -0.944 and -0.885. A
// mutation that ignores a^n gives -0.45 / -0.79, one with b 20 % high +0.59 / +0.30.
constexpr double kReflectionError = 0.16, kTransmissionError = 0.25;
// The same with the scattered-light cache (16 paths per texel, 2 voxels per texel, the 4 x 1 x 4
// slab), measured: reflection +0.018, transmission -0.053.
constexpr double kCacheReflectionError = 0.018, kCacheTransmissionError = 0.053;

// A slab 8 x 1 x 8 around the origin (extinction 4: tau = 4 across it), lit from above, seen
// by an orthographic camera from `eye` over its middle (1 x 1 world units on 16 x 16 pixels).
nlohmann::json slabScene(nlohmann::json eye, int octaves) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 16, "height": 16, "ambient": 0, "background": [0, 0, 0],
                 "tonemap": "clamp", "fog_steps": 256, "fog_jitter": false},
      "cameras": [{"name": "c", "type": "orthographic", "target": [0, 0, 0],
                   "ortho_height": 1, "near": 0.5, "far": 20}],
      "lights": [{"type": "directional", "direction": [0, -1, 0], "intensity": 1}],
      "volumes": [{"procedural": "box", "size": [8, 1, 8], "voxel_size": 0.0625,
                   "density_scale": 4, "albedo": 0.99, "anisotropy": 0.6}]})");
    doc["cameras"][0]["position"] = eye;
    doc["render"]["fog_octaves"] = octaves;
    doc["render"]["fog_octave_scattering"] = kCloudScattering;
    return doc;
}

double meanRadiance(const ImageF& image) {
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c)
                sum += image.at(x, y, c);
    return sum / (3.0 * image.width * image.height);
}

struct Comparison {
    double reference = 0.0, standardError = 0.0, single = 0.0, multiple = 0.0;
};

Comparison compare(const gpu::ContextInfo& info, const nlohmann::json& eye) {
    Comparison out;
    const scene::Scene ms = scene::parseScene(slabScene(eye, kCloudOctaves), sourceDir());
    const scene::Scene ss = scene::parseScene(slabScene(eye, 1), sourceDir());
    for (const scene::Scene* s : {&ss, &ms}) {
        frame::Renderer r(*s, info, {0, 0, "", "blend"});
        r.render();
        (s == &ss ? out.single : out.multiple) = meanRadiance(r.readHdr());
    }
    volume::PathTracerSettings settings;
    settings.spp = 32;
    const volume::VolumePathTracer tracer(ms, {volume::loadVolume(ms.volumes[0])}, settings);
    const volume::PathTracedImage pt = tracer.render(ms.cameras[0], 16, 16);
    out.reference = meanRadiance(pt.radiance);
    // The pixels' errors are independent: the mean's variance is the sum of theirs / n^2.
    double var = 0.0;
    const double n = 3.0 * 16 * 16;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c)
                var += std::pow(pt.standardError.at(x, y, c), 2.0);
    out.standardError = std::sqrt(var) / n;
    return out;
}

// The slab of slabScene() 4 x 1 x 4 with the scattered-light cache instead of octaves: 2 voxels
// per texel (32 x 8 x 32 texels), `samples` paths per texel.
nlohmann::json cachedSlabScene(nlohmann::json eye, int samples) {
    nlohmann::json doc = slabScene(std::move(eye), 1);
    doc["volumes"][0]["size"] = {4, 1, 4};
    doc["render"]["fog_scattered_light"] = true;
    doc["render"]["fog_scattered_light_samples"] = samples;
    doc["render"]["fog_scattered_light_cell"] = 2;
    return doc;
}

} // namespace

class FogMultipleScatteringTest : public GlTest {};

// The scattered-light cache (render.fog_scattered_light): the marcher's single scattering plus
// the cache's P1 in-scattering against the path tracer on the same slab. Its error is the
// P1 truncation of the arriving radiance, the texels' interpolation (8 across the slab) and
// the bake's noise; the tolerance is the measured error plus 3 standard errors of the
// reference and of the cache's noise.
TEST_F(FogMultipleScatteringTest, ScatteredLightCacheMatchesThePathTracerOnTheSlab) {
    struct View {
        const char* name;
        nlohmann::json eye;
        double measured;
    };
    for (const View& v : {View{"reflection", {0.0, 6.0, 3.0}, kCacheReflectionError},
                          View{"transmission", {0.0, -6.0, 3.0}, kCacheTransmissionError}}) {
        const scene::Scene s = scene::parseScene(cachedSlabScene(v.eye, 16), sourceDir());
        frame::Renderer r(s, info(), {0, 0, "", "blend"});
        r.render();
        const double gpu = meanRadiance(r.readHdr());
        volume::PathTracerSettings settings;
        settings.spp = 32;
        const volume::VolumePathTracer tracer(s, {volume::loadVolume(s.volumes[0])}, settings);
        const volume::PathTracedImage pt = tracer.render(s.cameras[0], 16, 16);
        const double ref = meanRadiance(pt.radiance);
        double var = 0.0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                for (int c = 0; c < 3; ++c)
                    var += std::pow(pt.standardError.at(x, y, c), 2.0);
        const double se = std::sqrt(var) / (3.0 * 16 * 16);
        const double rel = (gpu - ref) / ref;
        std::printf("cached slab %s: path tracer %.5f +- %.5f, cache %.5f (%+.1f%%)\n", v.name, ref,
                    se, gpu, 100.0 * rel);
        ASSERT_GT(ref, 1e-3) << v.name;
        EXPECT_LT(std::abs(rel), v.measured + 0.03 + 3.0 * se / ref) << v.name;
    }
}

TEST_F(FogMultipleScatteringTest, SlabReflectionAndTransmissionMatchThePathTracer) {
    struct View {
        const char* name;
        nlohmann::json eye;
        double measured; // |octaves - path tracer| / path tracer with the defaults, measured
    };
    for (const View& v : {View{"reflection", {0.0, 6.0, 3.0}, kReflectionError},
                          View{"transmission", {0.0, -6.0, 3.0}, kTransmissionError}}) {
        const Comparison c = compare(info(), v.eye);
        const double rel = std::abs(c.multiple - c.reference) / c.reference;
        const double relSingle = std::abs(c.single - c.reference) / c.reference;
        const double noise = 3.0 * c.standardError / c.reference;
        std::printf("slab %s: path tracer %.5f +- %.5f, octaves %.5f (%.1f%%), single %.5f "
                    "(%.1f%%)\n",
                    v.name, c.reference, c.standardError, c.multiple, 100.0 * rel, c.single,
                    100.0 * relSingle);
        ASSERT_GT(c.reference, 1e-3) << v.name;
        const double tolerance = v.measured + 0.03 + noise;
        EXPECT_LT(rel, tolerance) << v.name;
        EXPECT_GT(relSingle, tolerance) << v.name << ": single scattering must fail this test";
    }
}

} // namespace veil::test

namespace veil::test {

// The cache and the octaves both add multiple scattering; the cache's bake has no fog filling
// all space: either combination is one message naming the scene, not a wrong image.
TEST_F(FogMultipleScatteringTest, ScatteredLightCacheRefusesOctavesAndHomogeneousFog) {
    auto message = [&](nlohmann::json doc) {
        const scene::Scene s = scene::parseScene(doc, sourceDir());
        try {
            frame::Renderer r(s, info(), {0, 0, "", "blend"});
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    nlohmann::json octaves = cachedSlabScene({0.0, 6.0, 3.0}, 1);
    octaves["render"]["fog_octaves"] = 4;
    EXPECT_NE(message(octaves).find("render.fog_scattered_light and render.fog_octaves 4 both "
                                    "add multiple scattering"),
              std::string::npos)
        << message(octaves);
    nlohmann::json haze = cachedSlabScene({0.0, 6.0, 3.0}, 1);
    haze["volumes"].push_back({{"procedural", "homogeneous"}, {"density_scale", 0.1}});
    EXPECT_NE(message(haze).find("render.fog_scattered_light needs grid volumes and no "
                                 "homogeneous fog"),
              std::string::npos)
        << message(haze);
}

} // namespace veil::test
