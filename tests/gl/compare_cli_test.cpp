// `veil compare` through the real binary: metrics printed, the largest error located, heat map
// written, exit status 0 within --fail and 1 beyond it; unreadable, missing, mismatched and
// non-regular files (a device, a FIFO, a folder) are one line naming the file.
#include "io/image_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include <sys/stat.h>

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

TEST(CompareCliTest, NamesWhereTheLargestErrorIs) {
    ImageF a(16, 8, 3), b(16, 8, 3);
    a.at(3, 2, 1) = 0.5f;  // the largest: G at (3, 2)
    a.at(9, 5, 0) = 0.25f; // a smaller one elsewhere
    io::writeImage(dir() / "where-a.exr", a);
    io::writeImage(dir() / "where-b.exr", b);
    const CommandResult r =
        compare(shellQuote(dir() / "where-a.exr") + " " + shellQuote(dir() / "where-b.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("largest |a - b| 0.5 at x 3, y 2 (row 0 at the top), channel G "
                            "(image 0.5, reference 0)"),
              std::string::npos)
        << r.output;
    // Equal images have no such line.
    const CommandResult same =
        compare(shellQuote(dir() / "where-b.exr") + " " + shellQuote(dir() / "where-b.exr"));
    EXPECT_EQ(same.output.find("largest"), std::string::npos) << same.output;
}

TEST(CompareCliTest, DevicesAndFifosAreRefusedNotRead) {
    const fs::path a = image("dev-a.exr", 0.5f);
    const fs::path fifo = dir() / "pipe.exr";
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    // Without the check these would block forever: `timeout` turns a hang into status 124.
    for (const std::string& bad : {std::string("/dev/zero"), fifo.string()}) {
        CommandResult r = runCommand("timeout 20 " + veilExe() + " compare " + shellQuote(bad) +
                                     " " + shellQuote(a));
        expectOneErrorLine(r, "not a regular file");
        EXPECT_NE(r.output.find(bad), std::string::npos) << r.output;
        r = runCommand("timeout 20 " + veilExe() + " compare " + shellQuote(a) + " " +
                       shellQuote(bad));
        expectOneErrorLine(r, "not a regular file");
    }
    expectOneErrorLine(compare(shellQuote(dir()) + " " + shellQuote(a)), "is a folder");
    fs::remove(fifo);
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
        "x.txt", 2);
}

} // namespace veil::test
