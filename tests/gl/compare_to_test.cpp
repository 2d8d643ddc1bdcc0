// `veil render --compare-to FILE|cpu`: a stored image, with errors that are
// known in closed form, and the fog's CPU reference.
#include "support/test_support.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("compare_to"); }

const char* kPlane = R"({
  "render": {"width": 80, "height": 60, "background": 0.7},
  "cameras": [{"name": "low", "position": [0, 2, 4], "target": [0, 1, 0], "fov_y": 50}],
  "lights": [{"type": "directional", "direction": [0, -1, 0]}],
  "materials": {"m": {"base_color": 0.5}},
  "objects": [{"shape": {"type": "plane", "size": [40, 40]}, "material": "m"}]
})";

} // namespace

TEST(CompareToTest, StoredImageGivesTheClosedFormError) {
    const fs::path scene = dir() / "plane.json", stored = dir() / "stored.exr";
    std::ofstream(scene) << kPlane;
    CommandResult r =
        runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(stored));
    ASSERT_EQ(r.exitCode, 0) << r.output;

    // The same frame: identical.
    const fs::path same = dir() / "same.exr", sameReport = dir() / "same.json";
    r = runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(same) +
                   " --compare-to " + shellQuote(stored) + " --report " + shellQuote(sameReport));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("stored.exr: RMSE 0,"), std::string::npos) << r.output;
    EXPECT_EQ(readJson(sameReport)["compare"]["rmse"], 0.0);
    EXPECT_TRUE(fs::exists(dir() / "same-error.png"));

    // Background 0.7 -> 0.8 changes only the sky, by 0.1 in R, G and B: RMSE = 0.1 sqrt(f),
    // f the sky's share of the pixels, counted from the stored Z channel (no surface: Z is
    // veil:background_depth, the far plane's depth).
    auto in = OIIO::ImageInput::open(stored.string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec spec = in->spec();
    const int z = spec.channelindex("Z");
    ASSERT_GE(z, 0);
    std::vector<float> zs(std::size_t(spec.width) * spec.height);
    ASSERT_TRUE(in->read_image(0, 0, z, z + 1, OIIO::TypeDesc::FLOAT, zs.data()));
    const float far = std::stof(spec.get_string_attribute("veil:background_depth", "0"));
    ASSERT_GT(far, 0.0f);
    const double sky =
        double(std::count_if(zs.begin(), zs.end(), [&](float v) { return v >= far; })) /
        double(zs.size());
    ASSERT_GT(sky, 0.1);
    const fs::path brighter = dir() / "brighter.png", report = dir() / "brighter.json";
    r = runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(brighter) +
                   " --set render.background=0.8 --compare-to " + shellQuote(stored) +
                   " --report " + shellQuote(report));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // The GPU target is RGBA16F: 0.7 and 0.8 are each within 2^-12 of their half values.
    EXPECT_NEAR(readJson(report)["compare"]["rmse"].get<double>(), 0.1 * std::sqrt(sky), 3e-4)
        << r.output;
    EXPECT_EQ(readJson(report)["compare"]["against"], stored.string());

    // A different size is one clear error naming both sizes; nothing written.
    const fs::path small = dir() / "small.exr";
    fs::remove(small);
    r = runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(small) +
                   " --width 40 --height 30 --compare-to " + shellQuote(stored));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("is 80x60, the render is 40x30"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(small));
    r = runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(small) +
                   " --compare-to " + shellQuote(dir() / "missing.exr"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("missing.exr': no such image file"), std::string::npos) << r.output;
    // The output may not replace the image it is compared with.
    r = runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(stored) +
                   " --compare-to " + shellQuote(stored));
    EXPECT_EQ(r.exitCode, 1) << r.output;
}

// A ball of fog (no lights, no ambient) over a white background: the frame is T per pixel and
// the CPU reference L + T * background with L = 0. fog_test.cpp bounds |T_gpu - T_cpu| by
// 2e-3 plus quadrature and half-float storage terms for such a ball; RMSE must stay below
// 3e-3, while dropping the background term from the reference gives an RMSE of about 0.9.
TEST(CompareToTest, CpuFogReference) {
    const nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 64, "height": 64, "ambient": 0, "background": [1, 1, 1],
                 "fog_steps": 256, "fog_jitter": false},
      "cameras": [{"name": "c", "type": "orthographic", "position": [0, 0, 5],
                   "target": [0, 0, 0], "ortho_height": 2, "near": 1, "far": 10}],
      "volumes": [{"procedural": "sphere", "size": 1.0, "voxel_size": 0.02,
                   "density_scale": 1.5}]
    })");
    const fs::path scene = dir() / "ball.json", out = dir() / "ball.exr",
                   report = dir() / "ball.json.report.json";
    std::ofstream(scene) << doc.dump();
    CommandResult r =
        runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(out) +
                   " --compare-to cpu --report " + shellQuote(report));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("vs cpu: RMSE"), std::string::npos) << r.output;
    const nlohmann::json j = readJson(report);
    EXPECT_LT(j["compare"]["rmse"].get<double>(), 3e-3) << r.output;
    EXPECT_EQ(j["compare"]["against"], "cpu");

    // No volumes: refused before rendering.
    std::ofstream(dir() / "plane.json") << kPlane;
    r = runCommand(veilExe() + " render " + shellQuote(dir() / "plane.json") + " -o " +
                   shellQuote(dir() / "plane-cpu.exr") + " --compare-to cpu");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("has no volumes"), std::string::npos) << r.output;
}

// With surfaces in the scene the CPU reference (fog only) is compared with the frame rendered
// again without them: a dark box in front of half the ball leaves the RMSE at the fog-only
// bound of CpuFogReference (3e-3), where comparing the whole frame gives about 0.4.
TEST(CompareToTest, CpuReferenceComparesTheFogAlone) {
    const nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 48, "height": 48, "ambient": 0, "background": [1, 1, 1],
                 "fog_steps": 256, "fog_jitter": false},
      "cameras": [{"name": "c", "type": "orthographic", "position": [0, 0, 5],
                   "target": [0, 0, 0], "ortho_height": 2, "near": 1, "far": 10}],
      "materials": {"dark": {"base_color": 0.05}},
      "objects": [{"shape": {"type": "box", "size": [1, 2, 0.2]}, "material": "dark",
                   "transform": {"translate": [-0.5, 0, 1.5]}}],
      "volumes": [{"procedural": "sphere", "size": 1.0, "voxel_size": 0.04,
                   "density_scale": 1.5}]
    })");
    const fs::path scene = dir() / "ball-box.json", out = dir() / "ball-box.png",
                   report = dir() / "ball-box.report.json";
    std::ofstream(scene) << doc.dump();
    const CommandResult r =
        runCommand(veilExe() + " render " + shellQuote(scene) + " -o " + shellQuote(out) +
                   " --compare-to cpu --report " + shellQuote(report));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("compared: the fog alone (the frame rendered again without the "
                            "scene's 1 object(s)"),
              std::string::npos)
        << r.output;
    const nlohmann::json j = readJson(report);
    EXPECT_LT(j["compare"]["rmse"].get<double>(), 3e-3) << r.output;
    EXPECT_NE(j["compare"]["note"].get<std::string>().find("fog alone"), std::string::npos);
}

} // namespace veil::test
