// Work and memory estimated before anything is allocated (hangs and memory): a
// particle cloud over the geometry budget, a fog march over the sample limit and a smoothing
// over its work limit each end at once in one line naming the file, the estimate and the
// limit, with exit 1 and no output; below the limits the same commands work.
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() {
    const fs::path d = outputDir() / "work_limits";
    fs::create_directories(d);
    return d;
}

fs::path writeScene(const std::string& name, const std::string& text) {
    const fs::path p = dir() / name;
    std::ofstream(p) << text;
    return p;
}

// Runs the command, expecting a quick failure with every `expect` string in one line.
void expectRefused(const std::string& command, const fs::path& out,
                   const std::vector<std::string>& expect) {
    fs::remove(out);
    const auto t0 = std::chrono::steady_clock::now();
    const CommandResult r = runCommand(command);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_LT(s, 20.0) << "refused only after " << s << " s";
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    for (const std::string& e : expect)
        EXPECT_NE(r.output.find(e), std::string::npos) << e << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out));
}

const char* kCamera =
    R"("cameras": [{"name": "c", "position": [0, 0, 5]}], "materials": {"m": {"alpha": 0.5}})";

} // namespace

TEST(WorkLimitsTest, ParticleCloudOverTheGeometryBudgetIsRefusedBeforeAllocating) {
    const fs::path scene = writeScene(
        "particles.json", std::string("{") + kCamera +
                              R"(, "objects": [{"shape": {"type": "particles", "count": 67108864},
                                 "material": "m"}]})");
    const fs::path out = dir() / "particles.png";
    // 2^26 particles: 168 bytes each = 10752 MiB, over the 2048 MiB default.
    expectRefused(veilExe() + " render '" + scene.string() + "' -o '" + out.string() + "'", out,
                  {"particles.json", "/objects/0/shape/count", "10752 MiB",
                   "render.geometry_budget_mib = 2048"});
    // The budget is the property: 10,[McGuire16] particles (1.6 MiB) fail under 1 MiB, pass
    // under 2.
    const std::string small = " --width 32 --height 18 --set objects.0.shape.count=10000 ";
    expectRefused(veilExe() + " render '" + scene.string() + "'" + small +
                      "--set render.geometry_budget_mib=1 -o '" + out.string() + "'",
                  out, {"10000 particles", "render.geometry_budget_mib = 1"});
    const CommandResult ok =
        runCommand(veilExe() + " render '" + scene.string() + "'" + small +
                   "--set render.geometry_budget_mib=2 -o '" + out.string() + "'");
    EXPECT_EQ(ok.exitCode, 0) << ok.output;
}

TEST(WorkLimitsTest, FogOverTheSampleLimitIsRefusedBeforeLoadingVolumes) {
    const fs::path scene = sourceDir() / "datasets/scenes/fog.json";
    const fs::path out = dir() / "fog.png";
    expectRefused(veilExe() + " render '" + scene.string() + "' --width 2048 --height 2048 " +
                      "--set render.fog_steps=4096 -o '" + out.string() + "'",
                  out, {"fog.json", "4096 steps", "1.72e+10 samples", "render.fog_sample_limit"});
    // An explicit limit applies on any renderer, and 0 lifts it (checked at a small size).
    expectRefused(veilExe() + " render '" + scene.string() + "' --width 64 --height 36 " +
                      "--set render.fog_steps=64 --set render.fog_sample_limit=1000 -o '" +
                      out.string() + "'",
                  out, {"1.47e+05 samples", "limit of 1e+03"});
}

TEST(WorkLimitsTest, SmoothingOverTheWorkLimitIsRefusedBeforeRunning) {
    const fs::path scene =
        writeScene("sphere.json", std::string("{") + kCamera +
                                      R"(, "objects": [{"shape": {"type": "sphere", "radius": 1},
                              "material": "m"}]})");
    const fs::path out = dir() / "smooth.vdb";
    expectRefused(veilExe() + " voxelize '" + scene.string() + "' --res 256 --smooth 64 -o '" +
                      out.string() + "'",
                  out, {"sphere.json", "smoothing width 64", "voxel updates", "--smooth-limit"});
    const CommandResult ok = runCommand(veilExe() + " voxelize '" + scene.string() +
                                        "' --res 32 --smooth 2 -o '" + out.string() + "'");
    EXPECT_EQ(ok.exitCode, 0) << ok.output;
    EXPECT_TRUE(fs::exists(out));
}

} // namespace veil::test
