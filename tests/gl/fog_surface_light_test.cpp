// Surfaces lit by the scattered-light cache (docs/scattered-light.md "Surfaces lit by the cache",
// shaders/volume/scattered_light.glsl): an emissive, scattering box ("a fire") above a floor,
// the floor's radiance in the GPU frame (its diffuse albedo x the irradiance of the cache's P1
// radiance where rays from the floor enter the box) against the path tracer's irradiance at
// the same points (VolumePathTracer::surfaceIrradiance: cosine-weighted paths through the
// volume with the tracer's own transport, not the cache). Frames without a cache compile no
// surface-light code.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "grid/density_grid.h"
#include "integrators/path_tracer.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace veil::test {

namespace {

constexpr int kSize = 16;          // pixels per side
constexpr double kAlbedo = 0.5;    // the floor's diffuse albedo
constexpr double kBoxBottom = 0.1; // the box's lowest face: the floor is this far below it

// A 1 x 0.5 x 1 box of density 1 (tau 1 through its height), albedo 0.5, g 0.3, emitting
// (1, 0.5, 0.15) per unit length, kBoxBottom above a floor plane at y = 0, a dim sky. The
// camera is orthographic, in the gap, looking straight down at the floor under the box's middle
// (its rays never enter the box: the floor's pixels are its reflected radiance alone). The
// cache: 2 voxels per texel (8 x 4 x 8 texels), 256 paths each, baked on the CPU.
nlohmann::json fireOverFloor() {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 16, "height": 16, "ambient": [0.02, 0.02, 0.03],
                 "background": [0, 0, 0], "tonemap": "clamp", "fog_steps": 32,
                 "fog_jitter": false, "fog_scattered_light": true,
                 "fog_scattered_light_samples": 256, "fog_scattered_light_cell": 2,
                 "fog_scattered_light_bake": "cpu"},
      "cameras": [{"name": "under", "type": "orthographic", "position": [0, 0.05, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 0.8,
                   "near": 0.005, "far": 1}],
      "materials": {"floor": {"base_color": 0.5, "roughness": 1}},
      "objects": [{"name": "floor", "shape": {"type": "plane", "size": 4},
                   "material": "floor"}],
      "volumes": [{"name": "fire", "procedural": "box", "size": [1, 0.5, 1],
                   "voxel_size": 0.0625, "density_scale": 2, "albedo": 0.5,
                   "anisotropy": 0.3, "emission": [1.0, 0.5, 0.15]}]})");
    doc["volumes"][0]["transform"]["translate"] = {0.0, kBoxBottom + 0.25, 0.0};
    return doc;
}

struct Comparison {
    double gpu = 0.0, reference = 0.0, referenceError = 0.0; // mean luminance over the floor
};

double luminance(const glm::dvec3& c) { return glm::dot(c, glm::dvec3(0.2126, 0.7152, 0.0722)); }

// The frame (kSize x kSize, the scene's orthographic camera looking straight at a floor of
// diffuse albedo kAlbedo, normal n, through no volume) against the path tracer's
// albedo / pi x E at the pixels' floor points (every second pixel in each direction: 64
// points x `samples` paths).
Comparison compareFloor(const scene::Scene& s, const gpu::ContextInfo& info, int samples,
                        const glm::dvec3& n, double floorHeight) {
    frame::Renderer r(s, info, {kSize, kSize, "", "blend"});
    r.render();
    const gpu::ImageF hdr = r.readHdr();
    volume::PathTracerSettings settings;
    settings.seed = 7;
    const volume::VolumePathTracer tracer(s, {volume::loadVolume(s.volumes[0])}, settings);
    const scene::Camera& cam = s.cameras[0];
    const glm::dvec3 eye(cam.position);
    const glm::dvec3 forward = glm::normalize(glm::dvec3(cam.target) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(cam.up)));
    const glm::dvec3 down = glm::cross(forward, right); // image rows run along it
    const double size = cam.orthoHeight;
    Comparison c;
    double var = 0.0;
    int count = 0;
    for (int py = 0; py < kSize; py += 2)
        for (int px = 0; px < kSize; px += 2) {
            glm::dvec3 p = eye + ((px + 0.5) / kSize - 0.5) * size * right +
                           ((py + 0.5) / kSize - 0.5) * size * down;
            p -= (glm::dot(p, n) - floorHeight) * n; // onto the floor
            glm::dvec3 se;
            const glm::dvec3 e =
                tracer.surfaceIrradiance(p, n, samples, std::uint64_t(py * kSize + px), &se);
            c.gpu += luminance(glm::dvec3(hdr.at(px, py, 0), hdr.at(px, py, 1), hdr.at(px, py, 2)));
            c.reference += kAlbedo / std::numbers::pi * luminance(e);
            var += std::pow(kAlbedo / std::numbers::pi * luminance(se), 2.0);
            ++count;
        }
    c.gpu /= count;
    c.reference /= count;
    c.referenceError = std::sqrt(var) / count;
    std::printf("floor: GPU %.5g, path tracer %.5g +- %.2g (%+.1f %%)\n", c.gpu, c.reference,
                c.referenceError, 100.0 * (c.gpu / c.reference - 1.0));
    return c;
}

} // namespace

class FogSurfaceLightTest : public GlTest {};

// The floor under the fire within 15 % of the path tracer. Measured: +10.8 % (the GPU brighter;
// +11.0 % before the texels near the floor had 8 times the paths).
// What separates the two: the P1 truncation of the radiance leaving the box (P1 puts more of
// it near the face's normal than there is, and a floor below the box sees the directions near
// the normal best: +5 % with the floor at the box's face, +17 % 0.2 below it, +21 to +27 % 0.4
// below), the texels' size and trilinear interpolation (a texel's centre lies 1/16 inside the
// box: it holds a little of the light emitted below it), 32 fixed ray directions from each
// floor point, and the cache's and the reference's Monte Carlo noise (256 paths per texel; the
// reference's mean has a standard error under 2 %, checked, 1.2 % measured).
TEST_F(FogSurfaceLightTest, FireLightsTheFloorAsThePathTracer) {
    const Comparison c = compareFloor(scene::parseScene(fireOverFloor(), sourceDir()), info(), 64,
                                      {0.0, 1.0, 0.0}, 0.0);
    EXPECT_LT(c.referenceError, 0.02 * c.reference);
    EXPECT_NEAR(c.gpu / c.reference, 1.0, 0.15);
    // The sky alone (the ambient term) is a small part of it: the fire's light dominates.
    EXPECT_GT(c.reference, 4.0 * kAlbedo * 0.02);
    VEIL_EXPECT_NO_GL_ERROR();
}

double meanFloor(const nlohmann::json& doc, const gpu::ContextInfo& info) {
    const scene::Scene s = scene::parseScene(doc, sourceDir()); // the renderer keeps a reference
    frame::Renderer r(s, info, {kSize, kSize, "", "blend"});
    r.render();
    const gpu::ImageF hdr = r.readHdr();
    double sum = 0.0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            sum += luminance(glm::dvec3(hdr.at(x, y, 0), hdr.at(x, y, 1), hdr.at(x, y, 2)));
    return sum / (kSize * kSize);
}

// Transparent surfaces receive the same light: the floor at alpha 0.5 over the black background,
// drawn by the hardware rasterizer (transparent.frag) and by the compute rasterizer (fine.comp),
// is half the opaque floor (blend: alpha x reflected).
TEST_F(FogSurfaceLightTest, TransparentSurfacesReceiveTheSameLight) {
    const nlohmann::json opaque = fireOverFloor();
    const double full = meanFloor(opaque, info());
    for (const char* rasterizer : {"raster", "compute"}) {
        nlohmann::json doc = opaque;
        doc["materials"]["floor"]["alpha"] = 0.5;
        doc["render"]["oit_rasterizer"] = rasterizer;
        const double half = meanFloor(doc, info());
        std::printf("%s: transparent floor %.5g, opaque %.5g\n", rasterizer, half, full);
        EXPECT_NEAR(half / full, 0.5, 0.01) << rasterizer;
    }
    VEIL_EXPECT_NO_GL_ERROR();
}

// Without a cache the surface programs are compiled as before (no VEIL_SURFACE_SCATTERED_LIGHT)
// and the floor gets the ambient term alone.
TEST_F(FogSurfaceLightTest, WithoutACacheTheFloorGetsTheAmbientAlone) {
    nlohmann::json doc = fireOverFloor();
    doc["render"]["fog_scattered_light"] = false;
    const scene::Scene s = scene::parseScene(doc, sourceDir());
    frame::Renderer r(s, info(), {0, 0, "", "blend"});
    r.render();
    const gpu::ImageF hdr = r.readHdr();
    EXPECT_NEAR(hdr.at(kSize / 2, kSize / 2, 1), kAlbedo * 0.02, 1e-3); // ambient x albedo
    VEIL_EXPECT_NO_GL_ERROR();
}

// The cache's texels within a texel of an object's bounds trace
// render.fog_scattered_light_surface_factor times the paths (volume::
// scatteredLightSurfaceTexels): a floor close below the box reads few texels, so their bake
// noise shows on it unless they have more paths. The bake's noise on the floor is measured as
// the mean square difference between the floors of two bakes with other seeds (relative to the
// floor's mean), with the factor at 4 and at 1; with 4 times the paths it falls to 1/4. Its
// tolerance: the floor reads about 164 texels (13 x 13 of the bottom layer at 1 voxel per
// texel), each a pixel's worth, neighbouring pixels sharing them through the interpolation; at
// a conservative 40 independent values per estimate each mean square has a relative spread of
// sqrt(2 / 40) and their ratio a log-spread of sqrt(4 / 40) = 0.32, so the ratio lies within
// 0.25 x exp(+-3 x 0.32) = [0.10, 0.65] (a factor of 1 gives 1). Both bakes (the CPU path
// tracer and the compute shader's surface pass), and the two agree on the floor's mean within 4
// standard errors of their difference (each bake's error from the same mean squares).
TEST_F(FogSurfaceLightTest, TexelsNearASurfaceGetMorePaths) {
    constexpr double kGap = 0.03; // the floor below the box: half a texel
    nlohmann::json doc = fireOverFloor();
    doc["volumes"][0]["transform"]["translate"] = {0.0, kGap + 0.25, 0.0};
    doc["cameras"][0]["position"] = {0.0, 0.015, 0.0};
    doc["render"]["fog_scattered_light_cell"] = 1;
    doc["render"]["fog_scattered_light_samples"] = 16;
    const auto floorLuminance = [&](const char* bake, int factor, int seed) {
        nlohmann::json d = doc;
        d["render"]["fog_scattered_light_bake"] = bake;
        d["render"]["fog_scattered_light_surface_factor"] = factor;
        d["render"]["seed"] = seed;
        const scene::Scene s = scene::parseScene(d, sourceDir());
        frame::Renderer r(s, info(), {kSize, kSize, "", "blend"});
        r.render();
        const gpu::ImageF hdr = r.readHdr();
        std::vector<double> y;
        for (int py = 0; py < kSize; ++py)
            for (int px = 0; px < kSize; ++px)
                y.push_back(
                    luminance(glm::dvec3(hdr.at(px, py, 0), hdr.at(px, py, 1), hdr.at(px, py, 2))));
        return y;
    };
    const auto mean = [](const std::vector<double>& v) {
        double m = 0.0;
        for (double x : v)
            m += x;
        return m / double(v.size());
    };
    // The mean square difference of two bakes' floors (per pixel), over the mean squared.
    const auto noise = [&](const std::vector<double>& a, const std::vector<double>& b) {
        double d = 0.0;
        for (std::size_t i = 0; i < a.size(); ++i)
            d += (a[i] - b[i]) * (a[i] - b[i]);
        const double m = 0.5 * (mean(a) + mean(b));
        return d / double(a.size()) / (m * m);
    };
    double means[2] = {0.0, 0.0}, spread[2] = {0.0, 0.0};
    for (int b = 0; b < 2; ++b) {
        const char* bake = b == 0 ? "cpu" : "gpu";
        const std::vector<double> more1 = floorLuminance(bake, 4, 1),
                                  more2 = floorLuminance(bake, 4, 2),
                                  same1 = floorLuminance(bake, 1, 1),
                                  same2 = floorLuminance(bake, 1, 2);
        const double ratio = noise(more1, more2) / noise(same1, same2);
        std::printf("%s bake: floor noise (relative mean square) x4 paths %.4g, x1 %.4g, "
                    "ratio %.3f (expected 0.25)\n",
                    bake, noise(more1, more2), noise(same1, same2), ratio);
        EXPECT_GT(ratio, 0.10) << bake;
        EXPECT_LT(ratio, 0.65) << bake;
        means[b] = 0.5 * (mean(more1) + mean(more2));
        // One bake's floor mean: its per-pixel variance (half the mean square difference) over
        // 40 independent values; the mean of two bakes: half that.
        spread[b] = 0.5 * noise(more1, more2) * means[b] * means[b] / 40.0 / 2.0;
    }
    const double se = std::sqrt(spread[0] + spread[1]);
    std::printf("floor mean: CPU bake %.5g, GPU bake %.5g, difference %.2g standard errors\n",
                means[0], means[1], (means[1] - means[0]) / se);
    EXPECT_LT(std::abs(means[1] - means[0]), 4.0 * se);
    VEIL_EXPECT_NO_GL_ERROR();
}

// Not run by default (two 23k-texel CPU bakes: minutes on 2 cores):
// datasets/scenes/fire-floor.json, the EmberGen fire on its floor, seen from a camera between
// the floor and the grid's lowest voxels looking down at the floor under the flames.
//   veil_gl_tests --gtest_also_run_disabled_tests --gtest_filter='*EmberGen*'
// It also writes the scene's own view with the cache (fire-floor.png) and without it
// (fire-floor-before.png) to the test output folder.
TEST_F(FogSurfaceLightTest, DISABLED_EmberGenFireOnTheFloor) {
    scene::Scene s = scene::loadScene(sourceDir() / "datasets/scenes/fire-floor.json");
    for (bool cache : {true, false}) {
        scene::Scene view = s;
        view.render.fogScatteredLight = cache;
        frame::Renderer r(view, info(), {});
        r.render();
        io::writeImage(outputSubdir("fog_surface_light") /
                           (cache ? "fire-floor.png" : "fire-floor-before.png"),
                       r.readLdr());
    }
    scene::Camera& cam = s.cameras[0];
    cam.type = scene::CameraType::Orthographic;
    cam.position = {-4.5f, -28.5f, -129.5f}; // the floor at -130, the padded grid from -129.5
    cam.target = {-4.5f, -28.5f, -131.0f};
    cam.up = {0.0f, 1.0f, 0.0f};
    cam.orthoHeight = 80.0f;
    cam.nearPlane = 0.01f;
    cam.farPlane = 2.0f;
    // The scene's floor has diffuse albedo 0.5 (kAlbedo). Without the moon: its direct light on
    // the floor is the shadow technique's, not the cache's (the reference has none of it).
    s.lights.clear();
    // Measured on llvmpipe: GPU 0.01739, path tracer 0.01759 +- 0.00070 (-1.1 %); an earlier
    // build with 64 paths for every texel: GPU 0.01696, path tracer 0.01802 +- 0.00074 (-5.9 %).
    const Comparison c = compareFloor(s, info(), 64, {0.0, 0.0, 1.0}, -130.0);
    EXPECT_NEAR(c.gpu / c.reference, 1.0, 0.15);
}

} // namespace veil::test
