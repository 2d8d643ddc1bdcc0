// `veil compare` through the real binary: metrics printed, heat map written, exit status 0
// within --fail and 1 beyond it; unreadable, missing and mismatched files are one line
// naming the file.
#include "io/image_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("compare-cli"); }

// A w x h RGB image of value v + 0.01 x (a gradient that keeps SSIM defined).
fs::path image(const std::string& name, float v, int w = 24, int h = 16) {
    ImageF img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                img.at(x, y, c) = v + 0.01f * float(x + y);
    const fs::path p = dir() / name;
    io::writeImage(p, img);
    return p;
}

CommandResult compare(const std::string& argsText) {
    return runCommand(veilExe() + " compare " + argsText);
}

// Usage errors (a missing argument, a bad --metric or --fail) exit 2, unreadable or
// mismatched files 1 (README).
void expectOneErrorLine(const CommandResult& r, const std::string& mustContain, int exitCode = 1) {
    EXPECT_EQ(r.exitCode, exitCode) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find("veil: error:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(mustContain), std::string::npos) << r.output;
}

} // namespace

TEST(CompareCliTest, IdenticalImagesPassAndWriteAHeatMap) {
    const fs::path a = image("same-a.exr", 0.5f), b = image("same-b.exr", 0.5f);
    const fs::path diff = dir() / "same-diff.png";
    fs::remove(diff);
    const CommandResult r =
        compare(shellQuote(a) + " " + shellQuote(b) + " --fail 0 --diff " + shellQuote(diff));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* m : {"rmse", "maxabs", "relmse", "p99", "psnr", "ssim", "PASS"})
        EXPECT_NE(r.output.find(m), std::string::npos) << m << "\n" << r.output;
    EXPECT_NE(r.output.find("psnr    inf"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ssim    1"), std::string::npos) << r.output;
    ASSERT_TRUE(fs::exists(diff));
    const ImageF d = io::readImage(diff);
    EXPECT_EQ(d.width, 24);
    EXPECT_EQ(*std::max_element(d.pixels.begin(), d.pixels.end()), 0.0f);
}

TEST(CompareCliTest, ExitStatusFollowsFailThreshold) {
    // A constant offset of 0.125 (exact in half floats): rmse = maxabs = p99 = 0.125.
    const fs::path a = image("off-a.exr", 0.625f), b = image("off-b.exr", 0.5f);
    CommandResult r =
        compare(shellQuote(a) + " " + shellQuote(b) + " --metric rmse --metric maxabs --fail 0.1");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("rmse    0.125"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("FAILURE: rmse 0.125 > 0.1"), std::string::npos) << r.output;
    r = compare(shellQuote(a) + " " + shellQuote(b) + " --metric rmse --fail 0.2 --warn 0.1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("WARNING: rmse 0.125"), std::string::npos) << r.output;
    // METRIC=T forms; psnr and ssim are lower bounds.
    r = compare(shellQuote(a) + " " + shellQuote(b) +
                " --metric p99 --fail maxabs=0.13 --fail psnr=10");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    r = compare(shellQuote(a) + " " + shellQuote(b) + " --fail ssim=0.9999");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("FAILURE: ssim"), std::string::npos) << r.output;
}

TEST(CompareCliTest, HeatMapShowsWhereTheImagesDiffer) {
    ImageF a(16, 8, 3), b(16, 8, 3);
    a.at(3, 2, 1) = 1.0f;
    io::writeImage(dir() / "spot-a.exr", a);
    io::writeImage(dir() / "spot-b.exr", b);
    const fs::path diff = dir() / "spot-diff.png";
    const CommandResult r =
        compare(shellQuote(dir() / "spot-a.exr") + " " + shellQuote(dir() / "spot-b.exr") +
                " --diff " + shellQuote(diff) + " --diff-scale 1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageF d = io::readImage(diff);
    EXPECT_EQ(d.at(3, 2, 0) + d.at(3, 2, 1) + d.at(3, 2, 2), 3.0f); // white: error = scale
    EXPECT_EQ(d.at(4, 2, 0) + d.at(4, 2, 1) + d.at(4, 2, 2), 0.0f);
}

TEST(CompareCliTest, MissingUnreadableOrMismatchedFilesNameTheFile) {
    const fs::path a = image("ok-a.exr", 0.5f), small = image("ok-small.exr", 0.5f, 8, 8);
    expectOneErrorLine(compare(shellQuote(a) + " " + shellQuote(dir() / "nope.exr")), "nope.exr");
    std::ofstream(dir() / "garbage.exr") << "not an image";
    expectOneErrorLine(compare(shellQuote(dir() / "garbage.exr") + " " + shellQuote(a)),
                       "garbage.exr");
    const CommandResult r = compare(shellQuote(a) + " " + shellQuote(small));
    expectOneErrorLine(r, "24x16");
    EXPECT_NE(r.output.find("ok-small.exr"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("8x8"), std::string::npos) << r.output;
}

TEST(CompareCliTest, UsageErrorsAreOneLine) {
    const fs::path a = image("u-a.exr", 0.5f);
    expectOneErrorLine(compare(shellQuote(a) + " " + shellQuote(a) + " --metric mse"),
                       "unknown metric 'mse'", 2);
    expectOneErrorLine(compare(shellQuote(a) + " " + shellQuote(a) + " --fail rmse=abc"),
                       "not a finite number", 2);
    expectOneErrorLine(compare(shellQuote(a) + " " + shellQuote(a) + " --fail -1"), ">= 0", 2);
    expectOneErrorLine(compare(shellQuote(a)), "reference", 2);
    expectOneErrorLine(
        compare(shellQuote(a) + " " + shellQuote(a) + " --diff " + shellQuote(dir() / "x.txt")),
        "x.txt");
}

} // namespace veil::test
