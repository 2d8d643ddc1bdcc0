// Blackbody emission of a temperature grid (docs/volumes.md "Emission") in the GPU fog marcher,
// the CPU fog reference and the path tracer: a uniform, purely absorbing slab (albedo 0, no
// lights) at 1500 K and 6500 K, seen straight through. Its radiance is
// B(T) (1 - exp(-tau)) (emission = sigma_t B(T) with temperature_intensity 1), so every
// pixel's chromaticity (x, y) is the blackbody's: checked against the Planckian locus of
// Krystek's rational approximation [Krystek85] (as tests/unit/blackbody_test.cpp, which checks
// the integration itself), within 0.005. The GPU's magnitude is checked against
// B(T) (1 - exp(-tau)) too (half-float texels and output, the table's interpolation: 3 %).
// A colour (vec3) emission grid: GPU against the CPU reference. Bad grids (a vector grid as
// temperature, a missing name) end in one error naming the file and the grid.
#include "gl_fixture.h"

#include "base/error.h"
#include "frame/renderer.h"
#include "scene/scene.h"
#include "support/planckian_locus.h"
#include "support/test_support.h"
#include "integrators/blackbody.h"
#include "integrators/cpu_reference.h"
#include "grid/density_grid.h"
#include "integrators/path_tracer.h"

#include <openvdb/openvdb.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>

namespace veil::test {

namespace {

glm::dvec2 chromaticity(const glm::dvec3& rgb) {
    return xyChromaticity(volume::linearSrgbToXyz(rgb));
}

// density 1 in index box x, z in [-16, 15], y in [-4, 3] (voxel 1/16: 2 x 0.5 x 2 world units,
// trilinear thickness exactly 0.5), a temperature of 2 over two more voxels on every side (so
// the edges are not cooled by the interpolation), a colour (vec3) emission grid over the same
// box, and a vec3 grid of another size.
std::filesystem::path writeSlab() {
    openvdb::initialize();
    const auto xf = openvdb::math::Transform::createLinearTransform(1.0 / 16.0);
    auto density = openvdb::FloatGrid::create(0.0f);
    density->setName("density");
    density->setTransform(xf);
    density->denseFill(openvdb::CoordBBox({-16, -4, -16}, {15, 3, 15}), 1.0f, true);
    auto temperature = openvdb::FloatGrid::create(0.0f);
    temperature->setName("temperature");
    temperature->setTransform(xf);
    temperature->denseFill(openvdb::CoordBBox({-18, -6, -18}, {17, 5, 17}), 2.0f, true);
    auto glow = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    glow->setName("glow");
    glow->setTransform(xf);
    glow->denseFill(openvdb::CoordBBox({-18, -6, -18}, {17, 5, 17}),
                    openvdb::Vec3s(0.2f, 0.5f, 1.0f), true);
    auto velocity = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    velocity->setName("velocity");
    velocity->setTransform(xf);
    velocity->denseFill(openvdb::CoordBBox({-2, -2, -2}, {1, 1, 1}), openvdb::Vec3s(1.0f), true);
    const auto path = outputSubdir("fog_emission") / "slab.vdb";
    volume::saveGrids(path, {density, temperature, glow, velocity});
    return path;
}

// Seen from above through the middle (1 x 1 world units on 8 x 8 pixels), tau = 1.
nlohmann::json slabScene(const std::filesystem::path& vdb, double kelvin,
                         const std::string& grid = "temperature") {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 8, "height": 8, "ambient": 0, "background": [0, 0, 0],
                 "tonemap": "clamp", "fog_steps": 64, "fog_jitter": false},
      "cameras": [{"name": "c", "type": "orthographic", "position": [0, 3, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 1, "near": 0.5,
                   "far": 20}],
      "volumes": [{"name": "slab", "density_scale": 2, "albedo": 0}]})");
    doc["volumes"][0]["path"] = vdb.string();
    doc["volumes"][0]["temperature_grid"] = grid;
    doc["volumes"][0]["temperature_scale"] = (kelvin - 500.0) / 2.0; // T = scale x 2 + 500
    doc["volumes"][0]["temperature_offset"] = 500.0;
    return doc;
}

glm::dvec3 meanRgb(const ImageF& image) {
    glm::dvec3 sum(0.0);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            sum += glm::dvec3(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
    return sum / double(image.width * image.height);
}

void expectOnLocus(const glm::dvec3& rgb, double kelvin, const char* who) {
    const glm::dvec2 xy = chromaticity(rgb), ref = krystekXy(kelvin);
    std::printf("%s %.0f K: rgb (%.5g %.5g %.5g) xy (%.4f %.4f), locus (%.4f %.4f)\n", who, kelvin,
                rgb.x, rgb.y, rgb.z, xy.x, xy.y, ref.x, ref.y);
    EXPECT_NEAR(xy.x, ref.x, 0.005) << who << " " << kelvin << " K";
    EXPECT_NEAR(xy.y, ref.y, 0.005) << who << " " << kelvin << " K";
}

} // namespace

class FogEmissionTest : public GlTest {};

TEST_F(FogEmissionTest, UniformSlabGlowsWithTheBlackbodyColour) {
    const auto vdb = writeSlab();
    for (double kelvin : {1500.0, 6500.0}) {
        const scene::Scene s = scene::parseScene(slabScene(vdb, kelvin), sourceDir());
        const glm::dvec3 expected = volume::blackbodyRgb(kelvin) * (1.0 - std::exp(-1.0));

        frame::Renderer r(s, info(), {0, 0, "", "blend"});
        r.render();
        const glm::dvec3 gpu = meanRgb(r.readHdr());
        expectOnLocus(gpu, kelvin, "GPU");
        const double y = volume::linearSrgbToXyz(gpu).y, yRef = volume::blackbodyXyz(kelvin).y;
        EXPECT_NEAR(y / (yRef * (1.0 - std::exp(-1.0))), 1.0, 0.03) << kelvin << " K";
        VEIL_EXPECT_NO_GL_ERROR();

        const auto grid = volume::loadVolume(s.volumes[0]);
        const volume::CpuFogReference cpu(s, {grid});
        const glm::dvec3 cpuRgb = meanRgb(cpu.render(s.cameras[0], 8, 8, 64));
        expectOnLocus(cpuRgb, kelvin, "CPU reference");
        EXPECT_NEAR(cpuRgb.y / expected.y, 1.0, 0.01) << kelvin << " K";

        volume::PathTracerSettings settings;
        settings.spp = 4;
        const volume::VolumePathTracer tracer(s, {grid}, settings);
        const volume::PathTracedImage pt = tracer.render(s.cameras[0], 4, 4);
        const glm::dvec3 ptRgb = meanRgb(pt.radiance);
        expectOnLocus(ptRgb, kelvin, "path tracer");
        // The mean of 16 independent pixels: its standard error is theirs / 16 in quadrature.
        double var = 0.0;
        for (int py = 0; py < 4; ++py)
            for (int px = 0; px < 4; ++px)
                var += std::pow(pt.standardError.at(px, py, 1), 2.0);
        const double se = std::sqrt(var) / 16.0;
        std::printf("path tracer %.0f K: G %.5g +- %.2g, expected %.5g\n", kelvin, ptRgb.y, se,
                    expected.y);
        EXPECT_NEAR(ptRgb.y, expected.y, 3.0 * se + 0.01 * expected.y) << kelvin << " K";
    }
}

TEST_F(FogEmissionTest, ColourEmissionGridMatchesTheCpuReference) {
    // emission_grid "glow" (0.2, 0.5, 1) x emission (1, 2, 0.5) = (0.2, 1, 0.5) per unit length,
    // over a box two voxels larger than the density's (its topology widens the density's).
    const auto vdb = writeSlab();
    nlohmann::json doc = slabScene(vdb, 1500.0);
    doc["volumes"][0].erase("temperature_grid");
    doc["volumes"][0]["emission_grid"] = "glow";
    doc["volumes"][0]["emission"] = {1.0, 2.0, 0.5};
    const scene::Scene s = scene::parseScene(doc, sourceDir());
    frame::Renderer r(s, info(), {0, 0, "", "blend"});
    r.render();
    const glm::dvec3 gpu = meanRgb(r.readHdr());
    const auto grid = volume::loadVolume(s.volumes[0]);
    const glm::dvec3 cpu =
        meanRgb(volume::CpuFogReference(s, {grid}).render(s.cameras[0], 8, 8, 64));
    volume::PathTracerSettings settings;
    settings.spp = 4;
    const glm::dvec3 pt =
        meanRgb(volume::VolumePathTracer(s, {grid}, settings).render(s.cameras[0], 4, 4).radiance);
    std::printf("colour emission: GPU (%.5g %.5g %.5g), CPU reference (%.5g %.5g %.5g), path "
                "tracer (%.5g %.5g %.5g)\n",
                gpu.x, gpu.y, gpu.z, cpu.x, cpu.y, cpu.z, pt.x, pt.y, pt.z);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(gpu[c] / cpu[c], 1.0, 0.01) << c; // half-float texels and output
    // Every sample of the path tracer has the colour's ratios (one uniform colour).
    EXPECT_NEAR(pt.x / pt.y, 0.2, 1e-6);
    EXPECT_NEAR(pt.z / pt.y, 0.5, 1e-6);
    EXPECT_NEAR(cpu.x / cpu.y, 0.2, 1e-9);
    EXPECT_NEAR(cpu.z / cpu.y, 0.5, 1e-9);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(FogEmissionTest, ABadTemperatureGridIsOneErrorNamingFileAndGrid) {
    const auto vdb = writeSlab();
    struct Case {
        const char* grid;
        const char* says;
    };
    for (const Case& c : {Case{"velocity", "holds vec3s values; a temperature_grid must be a "
                                           "scalar float grid"},
                          Case{"heat", "has no grid named 'heat' (temperature_grid"}}) {
        const scene::Scene s = scene::parseScene(slabScene(vdb, 1500.0, c.grid), sourceDir());
        try {
            frame::Renderer r(s, info(), {0, 0, "", "blend"});
            ADD_FAILURE() << c.grid << ": no error";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(c.says), std::string::npos) << what;
            EXPECT_NE(what.find(vdb.string()), std::string::npos) << what;
        }
        EXPECT_THROW((void)volume::CpuFogReference(s, {volume::loadVolume(s.volumes[0])}), Error);
    }
    // The command line: exit status 1, one line naming the scene, the file and the grid, no
    // image written.
    const auto dir = outputSubdir("fog_emission");
    const auto scenePath =
        writeTextFile(dir / "bad.json", slabScene(vdb, 1500.0, "velocity").dump());
    const auto image = dir / "bad.png";
    std::filesystem::remove(image);
    const CommandResult r = runCommand(veilExe() + " render " + shellQuote(scenePath) + " -o " +
                                       shellQuote(image) + " 2>&1");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("bad.json: /volumes/0"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("grid 'velocity' of '" + vdb.string() + "' holds vec3s values"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(std::filesystem::exists(image));
}

} // namespace veil::test
