// The veil command against the hostile and careless inputs of a second campaign: empty
// option values, NaN and infinite numbers, NaN images, a --diff-scale of nan, vertices near
// FLT_MAX, shadow fog passes too large for the machine, a report on a full disk, interrupted
// and repeated dumps, --oit all to EXR. Each ends in one clear line and the right status,
// or in a correct result.
#include "base/image.h"
#include "io/exr_writer.h"
#include "io/image_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <sys/mount.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) { return freshOutputDir("reliability_cli", name); }

std::string q(const fs::path& p) { return shellQuote(p); }

const std::string kScene = R"({
  "render": {"width": 48, "height": 32},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0, 0]}],
  "lights": [{"type": "directional", "direction": [0, -1, 0]}],
  "materials": {"m": {"base_color": 0.5}, "glass": {"base_color": 0.8, "alpha": 0.4}},
  "objects": [{"shape": {"type": "box", "size": [1, 1, 1]}, "material": "m"},
              {"shape": {"type": "sphere", "radius": 0.6}, "material": "glass",
               "transform": {"translate": [0.4, 0.3, 0.8]}}]
})";

// Runs `veil <args>`: exit `status`, one "veil: error:" line holding every needle.
std::string expectError(const std::string& args, const std::vector<std::string>& needles,
                        int status) {
    const CommandResult r = runCommand(veilExe() + " " + args);
    EXPECT_EQ(r.exitCode, status) << args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("veil: error: ", 0), 0u) << r.output;
    for (const std::string& n : needles)
        EXPECT_NE(r.output.find(n), std::string::npos) << "'" << n << "' not in: " << r.output;
    return r.output;
}

void writeRgbExr(const fs::path& p, const ImageF& img) {
    io::ExrImage exr;
    exr.width = img.width;
    exr.height = img.height;
    exr.channels = {"R", "G", "B"};
    exr.pixels = img.pixels;
    io::writeExr(p, exr);
}

} // namespace

// Mutation: emptyArgument() returning "" -> every one of these exits 0 as if the option had
// not been given (the render is written, no dump, no report).
TEST(ReliabilityCliTest, EmptyOptionValuesAreUsageErrors) {
    const fs::path dir = freshDir("empty");
    const std::string s = q(writeTextFile(dir / "scene.json", kScene)), o = q(dir / "o.png");
    for (const std::string opt : {"--dump", "--report", "--compare-to", "--oit", "--camera",
                                  "--shadows", "--set", "--grid"})
        expectError("render " + s + " -o " + o + " " + opt + " ''",
                    {"option " + opt + " needs a value, not ''", "veil render --help"}, 2);
    expectError("render " + s + " -o " + o + " --report=", {"option --report needs a value"}, 2);
    expectError("render '' -o " + o, {"argument 2 is empty"}, 2);
    expectError("compare " + o + " " + o + " --fail ''", {"option --fail needs a value"}, 2);
    EXPECT_FALSE(fs::exists(dir / "o.png"));
}

// Mutation: finiteRange back to CLI::PositiveNumber / CLI::Range on --diff-scale, --exposure,
// --refine-budget-ms -> nan accepted (--diff-scale nan then crashed in the heat map).
TEST(ReliabilityCliTest, NonFiniteOptionNumbersAreUsageErrors) {
    const fs::path dir = freshDir("numbers");
    ImageF a(8, 8, 3);
    std::fill(a.pixels.begin(), a.pixels.end(), 0.5f);
    writeRgbExr(dir / "a.exr", a);
    const std::string ab = q(dir / "a.exr") + " " + q(dir / "a.exr");
    for (const char* v : {"nan", "inf", "-1", "0", "1e400", "1x"})
        expectError("compare " + ab + " --diff " + q(dir / "d.png") + " --diff-scale " + v,
                    {"--diff-scale"}, 2);
    expectError("compare " + ab + " --exposure nan", {"--exposure", "not a finite number"}, 2);
    const std::string s = q(writeTextFile(dir / "scene.json", kScene));
    expectError("view " + s + " --frames 1 --screenshot " + q(dir / "v.png") +
                    " --refine-budget-ms nan",
                {"--refine-budget-ms", "not a finite number"}, 2);
    EXPECT_FALSE(fs::exists(dir / "d.png"));
    EXPECT_FALSE(fs::exists(dir / "v.png"));
}

// Mutation: parseThresholds back on VEIL_CHECK -> exit 1 (an error while running) and no
// statement of what --fail accepts.
TEST(ReliabilityCliTest, CompareFailThresholdsAreParsedAsUsage) {
    const fs::path dir = freshDir("fail");
    ImageF a(8, 8, 3);
    std::fill(a.pixels.begin(), a.pixels.end(), 0.5f);
    writeRgbExr(dir / "a.exr", a);
    const std::string ab = "compare " + q(dir / "a.exr") + " " + q(dir / "a.exr");
    for (const char* v : {"abc", "-1", "nan", "inf", "rmse=", "bogus=1", "maxabs=nan"})
        expectError(
            ab + " --fail '" + v + "'",
            {"--fail '" + std::string(v) + "'", "expected T or METRIC=T", "rmse, maxabs, relmse"},
            2);
    // psnr and ssim are lower bounds: a negative one is a threshold like any other.
    EXPECT_EQ(runCommand(veilExe() + " " + ab + " --fail psnr=-5").exitCode, 0);
}

// Mutation: maxAbs back on std::max -> "maxabs 0 ok" and exit 0 for a NaN image.
TEST(ReliabilityCliTest, NanImagesFailCompareAndGetAHeatMap) {
    const fs::path dir = freshDir("nan");
    ImageF ref(8, 8, 3);
    std::fill(ref.pixels.begin(), ref.pixels.end(), 0.5f);
    ImageF img = ref;
    img.at(3, 3, 0) = std::numeric_limits<float>::quiet_NaN();
    writeRgbExr(dir / "ref.exr", ref);
    writeRgbExr(dir / "img.exr", img);
    const CommandResult r =
        runCommand(veilExe() + " compare " + q(dir / "img.exr") + " " + q(dir / "ref.exr") +
                   " --fail maxabs=1 --diff " + q(dir / "d.png") + " --diff-scale 0.5");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("maxabs  nan  FAIL"), std::string::npos) << r.output;
    const ImageF heat = io::readImage((dir / "d.png").string());
    EXPECT_NEAR(heat.at(3, 3, 0), 1.0f, 1e-3f); // NaN: white
    EXPECT_NEAR(heat.at(0, 0, 0), 0.0f, 1e-3f);
}

// Mutation: no kMaxMeshCoordinate check -> voxelize died of SIGSEGV in grid fitting and render
// drew a black frame with exit 0.
TEST(ReliabilityCliTest, MeshesNearFltMaxAreRefused) {
    const fs::path dir = freshDir("huge");
    const fs::path obj =
        writeTextFile(dir / "huge.obj", "v -3e38 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n");
    for (const char* extra : {" --res 16", " --res 1", " --res 16 --solid"})
        expectError("voxelize " + q(obj) + " --quiet -o " + q(dir / "v.vdb") + extra,
                    {"huge.obj", "lies beyond 1e+18"}, 1);
    EXPECT_FALSE(fs::exists(dir / "v.vdb"));
}

// Mutation: Renderer without checkShadowWork -> 4096^2 fog columns x 129 slices x 4 substeps
// (8.7e9 density samples per frame) ran for hours on llvmpipe.
TEST(ReliabilityCliTest, ShadowFogPassesOverTheWorkLimitAreRefusedAtOnce) {
    const fs::path dir = freshDir("shadow-work");
    const fs::path scene = writeTextFile(dir / "fog.json", R"({
      "render": {"width": 64, "height": 64, "fog_steps": 16},
      "cameras": [{"name": "c", "position": [0, 0.5, 3]}],
      "lights": [{"type": "spot", "position": [0, 3, 0], "target": [0, 0, 0], "intensity": 20}],
      "materials": {"glass": {"alpha": 0.5}},
      "objects": [{"shape": {"type": "sphere", "radius": 0.3}, "material": "glass"}],
      "volumes": [{"procedural": "smoke-ball", "size": [1, 1, 1], "voxel_size": 0.1}]})");
    const std::string base = "render " + q(scene) + " -o " + q(dir / "o.png") +
                             " --set render.shadows.type=transmittance-slicemap";
    const auto t0 = std::chrono::steady_clock::now();
    expectError(base + " --set render.shadows.fog_columns=4096",
                {"fog.json", "transmittance-slicemap", "4096^2 columns (fog_columns)", "129 slices",
                 "4 substeps", "over the limit of 3e+08", "render.fog_sample_limit"},
                1);
    expectError(base + " --set render.shadows.fog_columns=2048 --set render.shadows.slices=1024 "
                       "--set render.shadows.fog_substeps=64",
                {"2048^2 columns", "1025 slices", "64 substeps"}, 1);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              60.0 * kSlowBuildFactor);
    EXPECT_FALSE(fs::exists(dir / "o.png"));
    // The limit is the one the fog marcher has: 0 lifts it (not run here: it would take hours).
    // Below it the same scene renders.
    const CommandResult ok = runCommand(veilExe() + " " + base + " --width 32 --height 32");
    EXPECT_EQ(ok.exitCode, 0) << ok.output;
}

// Mutation: RunOutputs without its cleanup -> the image stays behind a failed report.
TEST(ReliabilityCliTest, AReportThatCannotBeWrittenLeavesNoImage) {
    const fs::path dir = freshDir("full");
    const fs::path full = dir / "mnt";
    fs::create_directories(full);
    if (::mount("tmpfs", full.c_str(), "tmpfs", 0, "size=64k") != 0)
        GTEST_SKIP() << "cannot mount a 64 KiB tmpfs at " << full << " (" << std::strerror(errno)
                     << "); run as root to test a full disk";
    {
        std::ofstream fill(full / "fill", std::ios::binary);
        fill << std::string(64 * 1024, 'x');
    }
    const std::string s = q(writeTextFile(dir / "scene.json", kScene));
    expectError("render " + s + " -o " + q(dir / "o.png") + " --report " + q(full / "r.json"),
                {(full / "r.json").string(), "No space left on device"}, 1);
    ::umount(full.c_str());
    EXPECT_FALSE(fs::exists(dir / "o.png"));
}

// Mutation: dumpFrame writing into DIR directly -> a stale file of an earlier dump stays, and
// a folder of other files is written into.
TEST(ReliabilityCliTest, DumpsReplaceTheFolderAsAWhole) {
    const fs::path dir = freshDir("dump");
    const std::string s = q(writeTextFile(dir / "scene.json", kScene));
    const std::string render = "render " + s + " -o " + q(dir / "o.png") + " --oit blend --dump ";
    fs::create_directories(dir / "other");
    writeTextFile(dir / "other" / "notes.txt", "mine");
    expectError(render + q(dir / "other"), {"other", "holds files but no manifest.json"}, 1);
    EXPECT_TRUE(fs::exists(dir / "other" / "notes.txt"));
    // An earlier dump is replaced: its stale file goes, the manifest is there, nothing hidden
    // is left beside it.
    fs::create_directories(dir / "d");
    writeTextFile(dir / "d" / "manifest.json", "{}");
    writeTextFile(dir / "d" / "stale.exr", "old");
    const CommandResult r = runCommand(veilExe() + " " + render + q(dir / "d"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "d" / "manifest.json"));
    EXPECT_FALSE(fs::exists(dir / "d" / "stale.exr"));
    // A new folder given with a trailing slash (its parent is the folder above).
    const CommandResult slash = runCommand(veilExe() + " " + render + q(dir / "fresh") + "/");
    ASSERT_EQ(slash.exitCode, 0) << slash.output;
    EXPECT_TRUE(fs::exists(dir / "fresh" / "manifest.json"));
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

// Mutation: the all-techniques branch back to a contact sheet for EXR -> a 3-channel sheet of
// tiles, --half ignored, no Z and no metadata.
TEST(ReliabilityCliTest, OitAllToExrWritesOneLayerPerTechnique) {
    const fs::path dir = freshDir("oit-all");
    const std::string s = q(writeTextFile(dir / "scene.json", kScene));
    const CommandResult r = runCommand(veilExe() + " render " + s + " -o " + q(dir / "all.exr") +
                                       " --oit all --half --width 32 " + "--height 24");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    auto in = OIIO::ImageInput::open((dir / "all.exr").string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.width, 32);
    EXPECT_EQ(spec.height, 24);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::HALF);
    const auto has = [&](const std::string& c) {
        return std::find(spec.channelnames.begin(), spec.channelnames.end(), c) !=
               spec.channelnames.end();
    };
    for (const char* c : {"R", "G", "B", "A", "Z", "blend.R", "blend.G", "blend.B", "wboit.R"})
        EXPECT_TRUE(has(c)) << c;
    EXPECT_NE(spec.get_string_attribute("veil:layers").find("blend.R,G,B: blend"),
              std::string::npos);
    EXPECT_EQ(spec.get_string_attribute("veil:oit"), "all");
}

} // namespace veil::test
