// `veil render file.vdb`: a bare volume framed by a default camera and light.
#include "support/test_support.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("render_vdb"); }

} // namespace

TEST(RenderVdbTest, BareVolumeIsFramedAndLit) {
    const fs::path vdb = dataDir() / "vdb-sphere-fog" / "sphere.vdb", out = dir() / "sphere.exr",
                   report = dir() / "sphere.json";
    fs::remove(out);
    const CommandResult r =
        runCommand(veilExe() + " render " + shellQuote(vdb) + " -o " + shellQuote(out) +
                   " --width 64 --height 64 --report " + shellQuote(report));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("grid 0 'density' (float, 465 active voxels"), std::string::npos)
        << r.output;
    auto in = OIIO::ImageInput::open(out.string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec spec = in->spec();
    std::vector<float> px(std::size_t(64) * 64 * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    const int z = spec.channelindex("Z");
    const float background = std::stof(spec.get_string_attribute("veil:background_depth", "0"));
    EXPECT_GT(background, 0.0f);
    auto at = [&](int x, int y, int c) {
        return px[(std::size_t(y) * 64 + x) * spec.nchannels + c];
    };
    // The whole bounding sphere is in view: every border pixel is the background (0.02, 0.02,
    // 0.03, within half-float rounding), while the centre looks through the ball.
    const float bg[3] = {0.02f, 0.02f, 0.03f};
    for (int i = 0; i < 64; ++i)
        for (const auto& [x, y] :
             {std::pair{i, 0}, std::pair{i, 63}, std::pair{0, i}, std::pair{63, i}})
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(at(x, y, c), bg[c], 1e-4) << x << "," << y;
    double centre = 0.0;
    for (int c = 0; c < 3; ++c)
        centre += std::abs(at(32, 32, c) - bg[c]);
    EXPECT_GT(centre, 0.03) << "the volume is not in the middle of the image";
    // The ball is inscribed in the grid's box (2.2 x 1.8 x 2.2 world units), whose corners
    // reach 90% of the view: the camera is 4.5 units away, the ball of radius about 1 seen at
    // asin(1 / 4.5) = 12.8 deg of the 20 deg half field, about 63% of the width (less where
    // its density fades). Too near or too far a camera moves it out of [45%, 80%].
    int left = 64, right = -1;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            double d = 0.0;
            for (int c = 0; c < 3; ++c)
                d += std::abs(at(x, y, c) - bg[c]);
            if (d > 2e-3) left = std::min(left, x), right = std::max(right, x);
        }
    const double width = (right - left + 1) / 64.0;
    std::printf("volume spans %.0f%% of the width\n", 100.0 * width);
    EXPECT_GT(width, 0.45);
    EXPECT_LT(width, 0.80);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            EXPECT_EQ(at(x, y, z), background); // no opaque surface: the far plane's depth
    std::ifstream rep(report);
    const nlohmann::json j = nlohmann::json::parse(rep);
    EXPECT_EQ(j["camera"], "vdb");
    ASSERT_EQ(j["volumes"].size(), 1u);
    EXPECT_EQ(j["volumes"][0]["active_voxels"], 465);
}

TEST(RenderVdbTest, GridChoiceAndErrors) {
    // torus01.vdb's only grid is not called "density": the first float grid is taken.
    const fs::path torus = dataDir() / "vdb-torus-fog" / "torus01.vdb";
    CommandResult r = runCommand(veilExe() + " render " + shellQuote(torus) + " -o " +
                                 shellQuote(dir() / "torus.png") + " --width 48 --height 48");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("grid 0 'voxel_fog_density'"), std::string::npos) << r.output;
    const fs::path three = dataDir() / "vdb-three-density-grids" / "grids.vdb";
    const fs::path out = dir() / "bad.png";
    fs::remove(out);
    for (const auto& [args, expect] : std::vector<std::pair<std::string, std::string>>{
             {fmt::format("{} --grid smoke", shellQuote(three)),
              "grids.vdb' has no grid named 'smoke'"},
             {fmt::format("{} --grid 1", shellQuote(three)),
              "grid 1 shares its name 'density' with grid 0"},
             {shellQuote(dataDir() / "vdb-smoke" / "missing.vdb"), "missing.vdb"}}) {
        r = runCommand(veilExe() + " render " + args + " -o " + shellQuote(out) +
                       " --width 32 --height 32");
        EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(expect), std::string::npos) << args << "\n" << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_FALSE(fs::exists(out));
    }
}

} // namespace veil::test
