// `veil render --oit NAME --compare-to reference` and `--oit all` through the real command.
#include "io/image_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

namespace veil::test {

namespace fs = std::filesystem;

namespace {
std::string glassScene() { return (sourceDir() / "datasets/scenes/oit-glass.json").string(); }
} // namespace

TEST(OitCliGLTest, CompareReferenceWithItselfIsZero) {
    const fs::path dir = outputDir() / "oit-cli";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path out = dir / "self.png", report = dir / "self.json";
    const CommandResult r = runCommand(
        veilExe() + " render " + glassScene() + " --oit reference --compare-to " +
        "reference --width 96 --height 54 -o " + out.string() + " --report " + report.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(out));
    EXPECT_TRUE(fs::exists(dir / "self-error.png"));
    EXPECT_NE(r.output.find("RMSE 0,"), std::string::npos) << r.output;
    const nlohmann::json j = readJson(report);
    EXPECT_EQ(j["compare"]["rmse"].get<double>(), 0.0);
    EXPECT_EQ(j["compare"]["psnr_db"], "inf");
}

TEST(OitCliGLTest, CompareWboitReportsNonZeroError) {
    const fs::path dir = outputDir() / "oit-cli";
    fs::create_directories(dir);
    const fs::path out = dir / "wboit.png";
    const CommandResult r = runCommand(veilExe() + " render " + glassScene() +
                                       " --oit wboit --compare-to reference --width 96 "
                                       "--height 54 -o " +
                                       out.string() + " --report " + (dir / "wboit.json").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "wboit-error.png"));
    const nlohmann::json j = readJson(dir / "wboit.json");
    EXPECT_GT(j["compare"]["rmse"].get<double>(), 0.0);
    EXPECT_TRUE(j["compare"]["psnr_db"].is_number());
}

TEST(OitCliGLTest, AllTechniquesContactSheet) {
    const fs::path dir = outputDir() / "oit-cli";
    fs::create_directories(dir);
    const fs::path out = dir / "sheet.png";
    fs::remove(out);
    const CommandResult r =
        runCommand(veilExe() + " render " + glassScene() + " --oit all --width 96 --height 54 -o " +
                   out.string() + " --report " + (dir / "sheet.json").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    ASSERT_TRUE(fs::exists(out));
    const nlohmann::json j = readJson(dir / "sheet.json");
    ASSERT_GE(j["techniques"].size(), 3u);
    bool sawReference = false;
    for (const auto& t : j["techniques"]) {
        EXPECT_NE(r.output.find(t["oit"].get<std::string>()), std::string::npos);
        if (t["oit"] == "reference") {
            sawReference = true;
            EXPECT_EQ(t["compare"]["rmse"].get<double>(), 0.0);
        } else {
            EXPECT_GT(t["compare"]["rmse"].get<double>(), 0.0) << t["oit"];
        }
    }
    EXPECT_TRUE(sawReference);
    // A grid near 16:9 with a caption strip under each 96x54 tile, not one long row.
    const ImageF sheet = io::readImage(out);
    const double aspect = double(sheet.width) / sheet.height;
    EXPECT_GT(aspect, 1.0) << sheet.width << "x" << sheet.height;
    EXPECT_LT(aspect, 3.0) << sheet.width << "x" << sheet.height;
    EXPECT_GT(sheet.height, 54 + 20);
}

TEST(OitCliGLTest, UnknownTechniqueFailsAndListsNames) {
    const fs::path dir = outputDir() / "oit-cli";
    fs::create_directories(dir);
    const fs::path out = dir / "unknown.png";
    fs::remove(out);
    const CommandResult r =
        runCommand(veilExe() + " render " + glassScene() + " --oit no-such-oit -o " + out.string());
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("no-such-oit"), std::string::npos) << r.output;
    for (const char* name : {"blend", "reference", "wboit"})
        EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(dir / "unknown.json"));
    const CommandResult r2 = runCommand(veilExe() + " render " + glassScene() +
                                        " --oit blend --compare-to nope -o " + out.string());
    EXPECT_NE(r2.exitCode, 0);
    EXPECT_NE(r2.output.find("known:"), std::string::npos) << r2.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(OitCliGLTest, ShadowsAllSheetComparesEveryShadowTechniqueWithReference) {
    const fs::path dir = outputDir() / "oit-cli";
    fs::create_directories(dir);
    const fs::path out = dir / "shadows-sheet.png";
    fs::remove(out);
    const CommandResult r =
        runCommand(veilExe() + " render " + glassScene() +
                   " --shadows all --oit reference --width 64 --height 36 -o " + out.string() +
                   " --report " + (dir / "shadows-sheet.json").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json j = readJson(dir / "shadows-sheet.json");
    EXPECT_EQ(j["shadows"], "all");
    ASSERT_GE(j["techniques"].size(), 4u);
    EXPECT_EQ(j["techniques"][0]["shadows"], "reference");
    EXPECT_EQ(j["techniques"][0]["compare"]["rmse"].get<double>(), 0.0);
    bool someDiffer = false;
    for (const auto& t : j["techniques"]) {
        const std::string name = t["shadows"].get<std::string>();
        EXPECT_NE(r.output.find("shadows:" + name), std::string::npos) << r.output;
        EXPECT_EQ(t["compare"]["against"], "shadows:reference");
        someDiffer = someDiffer || t["compare"]["rmse"].get<double>() > 0.0;
    }
    EXPECT_TRUE(someDiffer) << r.output;
    const ImageF sheet = io::readImage(out);
    EXPECT_GT(sheet.height, 36 + 20);
}

} // namespace veil::test
