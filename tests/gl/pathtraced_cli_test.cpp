// `veil render --integrator pathtraced` and `--compare-to pathtraced`: the path tracer's image
// and standard-error files, and bad input ending in one clear line.
#include "support/test_support.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("pathtraced_cli"); }

nlohmann::json ballScene() {
    return nlohmann::json::parse(R"({
      "render": {"width": 16, "height": 16, "background": 1.0, "ambient": 0.0,
                 "pathtraced": {"spp": 8, "seed": 3}},
      "cameras": [{"name": "c", "type": "orthographic", "position": [0, 0, 5],
                   "target": [0, 0, 0], "ortho_height": 2, "near": 1, "far": 10}],
      "volumes": [{"procedural": "sphere", "size": 1.0, "voxel_size": 0.05,
                   "density_scale": 2.0, "albedo": 0.0}]
    })");
}

std::vector<float> readRgb(const fs::path& p, int& w, int& h) {
    auto in = OIIO::ImageInput::open(p.string());
    EXPECT_TRUE(in) << p;
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    w = spec.width;
    h = spec.height;
    std::vector<float> px(std::size_t(w) * h * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
    return px;
}

} // namespace

TEST(PathTracedCliTest, WritesImageAndStandardError) {
    const fs::path scene = dir() / "ball.json", out = dir() / "ball-pt.exr";
    std::ofstream(scene) << ballScene().dump();
    CommandResult r = runCommand(veilExe() + " render " + shellQuote(scene) +
                                 " --integrator pathtraced -o " + shellQuote(out));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("8 spp"), std::string::npos) << r.output;
    int w = 0, h = 0;
    const std::vector<float> img = readRgb(out, w, h);
    ASSERT_EQ(w, 16);
    // A corner ray misses the ball and sees the background exactly; the centre ray crosses
    // an absorbing ball (albedo 0), so it sees the background times a transmittance < 1.
    EXPECT_FLOAT_EQ(img[0], 1.0f);
    EXPECT_LT(img[(8 * 16 + 8) * 3], 0.5f);
    const std::vector<float> se = readRgb(dir() / "ball-pt-stderr.exr", w, h);
    ASSERT_EQ(w, 16);
    EXPECT_EQ(se[0], 0.0f);

    // The GPU frame against it.
    r = runCommand(veilExe() + " render " + shellQuote(scene) + " -o " +
                   shellQuote(dir() / "ball-gpu.exr") + " --compare-to pathtraced");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("vs pathtraced: RMSE"), std::string::npos) << r.output;
}

// The registry's other integrator by the same option: the fog marcher's CPU reference is
// deterministic, so it writes no standard-error image; the same ball, the same background.
TEST(PathTracedCliTest, FogMarchIntegratorThroughTheRegistry) {
    const fs::path scene = dir() / "ball-fm.json", out = dir() / "ball-fm.exr";
    std::ofstream(scene) << ballScene().dump();
    CommandResult r = runCommand(veilExe() + " render " + shellQuote(scene) +
                                 " --integrator fog-march -o " + shellQuote(out));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    int w = 0, h = 0;
    const std::vector<float> img = readRgb(out, w, h);
    ASSERT_EQ(w, 16);
    EXPECT_FLOAT_EQ(img[0], 1.0f);
    EXPECT_LT(img[(8 * 16 + 8) * 3], 0.5f);
    EXPECT_FALSE(fs::exists(dir() / "ball-fm-stderr.exr"));

    r = runCommand(veilExe() + " render " + shellQuote(scene) + " --integrator nope -o " +
                   shellQuote(dir() / "nope.exr"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("fog-march"), std::string::npos) << r.output;
}

TEST(PathTracedCliTest, BadInputIsOneClearLine) {
    nlohmann::json doc = ballScene();
    doc["render"]["pathtraced"]["max_bounces"] = 0;
    std::ofstream(dir() / "bad.json") << doc.dump();
    CommandResult r = runCommand(veilExe() + " render " + shellQuote(dir() / "bad.json") +
                                 " --integrator pathtraced -o " + shellQuote(dir() / "bad.exr"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("/render/pathtraced/max_bounces"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "bad.exr"));

    doc = ballScene();
    doc["volumes"].push_back({{"procedural", "homogeneous"}, {"density_scale", 0.1}});
    std::ofstream(dir() / "haze.json") << doc.dump();
    r = runCommand(veilExe() + " render " + shellQuote(dir() / "haze.json") +
                   " --integrator pathtraced -o " + shellQuote(dir() / "haze.exr"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("homogeneous fog filling all space"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "haze.exr"));
}

} // namespace veil::test
