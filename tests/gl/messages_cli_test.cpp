// What a first-time user reads: each message names the thing it is about in plain words, and
// a misspelt name is answered with the nearest known one.
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <fstream>
#include <regex>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("messages_cli"); }

CommandResult veil(const std::string& args) { return runCommand(veilExe() + " " + args + " 2>&1"); }

std::string scene(const std::string& name) {
    return shellQuote(sourceDir() / "datasets" / "scenes" / name);
}

// A .vdb of one ball (radius `radius` voxels of 0.05, density rho) named `name`.
fs::path ballVdb(const std::string& file, double radius, float rho) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.05));
    auto acc = grid->getAccessor();
    const int r = static_cast<int>(std::ceil(radius));
    for (int z = -r; z <= r; ++z)
        for (int y = -r; y <= r; ++y)
            for (int x = -r; x <= r; ++x)
                if (x * x + y * y + z * z <= radius * radius) acc.setValue({x, y, z}, rho);
    const fs::path p = dir() / file;
    openvdb::io::File(p.string()).write({grid});
    return p;
}

} // namespace

TEST(MessagesCli, InfoNamesTheHomogeneousHaze) {
    const CommandResult r = veil("info " + scene("fog.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("(homogeneous haze filling the scene, density_scale"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("volume      grid"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("smoke.vdb grid 'density', density_scale"), std::string::npos)
        << r.output;
}

TEST(MessagesCli, VdbWithoutAFloatGridSaysSoInEnglish) {
    openvdb::initialize();
    auto velocity = openvdb::Vec3SGrid::create();
    velocity->setName("vel");
    velocity->tree().setValue({0, 0, 0}, openvdb::Vec3s(1, 0, 0));
    const fs::path vdb = dir() / "vec3-only.vdb";
    openvdb::io::File(vdb.string()).write({velocity});
    const CommandResult r =
        veil("render " + shellQuote(vdb) + " -o " + shellQuote(dir() / "vec3.png"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("vec3-only.vdb': none of its grids is a float (density) grid "
                            "(grids: 0 'vel' (vec3s))"),
              std::string::npos)
        << r.output;
}

TEST(MessagesCli, MisspeltShadowTechniqueGetsTheNearestName) {
    const CommandResult r = veil("render " + scene("fog.json") + " --shadows momnet -o " +
                                 shellQuote(dir() / "momnet.png"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("--shadows: unknown shadow technique 'momnet' (did you mean "
                            "'moment'?)"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir() / "momnet.png"));
    const CommandResult o = veil("render " + scene("fog.json") + " --oit refrence -o " +
                                 shellQuote(dir() / "refrence.png"));
    EXPECT_NE(o.output.find("unknown OIT technique 'refrence' (did you mean 'reference'?)"),
              std::string::npos)
        << o.output;
}

TEST(MessagesCli, OptionOfAnotherCommandIsNamedWithItsCommand) {
    const CommandResult r = veil("render " + scene("fog.json") + " -o " +
                                 shellQuote(dir() / "frame.png") + " --script s.txt");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("'--script' is not an option of render; did you mean '--script' of "
                            "veil view?"),
              std::string::npos)
        << r.output;
    // Near nothing anywhere: the command's options are listed.
    const CommandResult far = veil("info " + scene("fog.json") + " --zzzzzzzzz");
    EXPECT_EQ(far.exitCode, 2) << far.output;
    EXPECT_NE(far.output.find("'--zzzzzzzzz' is not an option of info: --grid"), std::string::npos)
        << far.output;
}

TEST(MessagesCli, NonJsonSceneIsNamedByItsFormat) {
    const fs::path nvdb = dir() / "sphere.nvdb";
    std::ofstream(nvdb, std::ios::binary) << std::string("NanoVDB0\x20\x00\x00\x00", 12);
    const CommandResult r =
        veil("render " + shellQuote(nvdb) + " -o " + shellQuote(dir() / "nvdb.png"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("sphere.nvdb' is a NanoVDB grid (.nvdb), which veil does not read"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("invalid JSON"), std::string::npos) << r.output;
    // An OpenVDB file under another name is recognised by its magic number.
    const fs::path renamed = dir() / "ball.data";
    fs::copy_file(ballVdb("ball-renamed.vdb", 4, 1.0f), renamed,
                  fs::copy_options::overwrite_existing);
    const CommandResult v = veil("info " + shellQuote(renamed));
    EXPECT_EQ(v.exitCode, 1) << v.output;
    EXPECT_NE(v.output.find("is an OpenVDB file: name it *.vdb"), std::string::npos) << v.output;
}

TEST(MessagesCli, VersionNamesTheCommit) {
    const CommandResult r = veil("--version");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    // A git checkout gives `git describe` (12 hex digits, after a tag's name and distance when
    // there is one; "-dirty" with uncommitted changes); a tree without history says "unknown".
    EXPECT_TRUE(std::regex_search(
        r.output,
        std::regex(R"(^veil \d+\.\d+\.\d+ \(commit ([^ ]*[0-9a-f]{12}(-dirty)?|unknown))")))
        << r.output;
}

TEST(MessagesCli, UsageErrorsExitTwoAsTheDocsSay) {
    const CommandResult r = veil("compare a.exr b.exr --metrc rmse");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    std::ifstream in(sourceDir() / "docs" / "regression.md");
    const std::string docs{std::istreambuf_iterator<char>(in), {}};
    EXPECT_NE(docs.find("exit status 2, like every `veil` command"), std::string::npos);
    EXPECT_EQ(docs.find("exit status 1, like every `veil` command"), std::string::npos);
}

TEST(MessagesCli, BareVdbDensityScaleFromTheDataAndAsOverridden) {
    // A ball of radius R and density rho: the median line of sight has optical depth
    // 2 sqrt(R^2 - (R + h)^2 / 2) rho (tests/unit/optical_depth_test.cpp), the scale 1.5 / that.
    const double radiusVoxels = 12.0, rho = 4.0;
    const fs::path vdb = ballVdb("ball.vdb", radiusVoxels, float(rho));
    const std::string out = shellQuote(dir() / "ball.png");
    const CommandResult r =
        veil("render " + shellQuote(vdb) + " -o " + out + " --width 24 --height 24");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(density_scale ([0-9.e+-]+) \()")))
        << r.output;
    const double radius = radiusVoxels * 0.05, rh = radius + 0.05;
    const double expected = 1.5 / (2.0 * std::sqrt(radius * radius - rh * rh / 2.0) * rho);
    EXPECT_NEAR(std::stod(m[1].str()), expected, 0.04 * expected) << r.output;
    EXPECT_NE(r.output.find("median optical depth 1.5 along the view"), std::string::npos)
        << r.output;
    // After --set the line states the value rendered, and the default beside it.
    const CommandResult o = veil("render " + shellQuote(vdb) + " -o " + out +
                                 " --width 24 --height 24 --set volumes.0.density_scale=0.05");
    ASSERT_EQ(o.exitCode, 0) << o.output;
    EXPECT_NE(o.output.find("density_scale 0.05 (set by --set; the default is"), std::string::npos)
        << o.output;
}

} // namespace veil::test
