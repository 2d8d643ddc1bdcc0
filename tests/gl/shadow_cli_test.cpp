// Shadow techniques through the veil command: --shadows, the report's shadow fields, and
// --compare-to shadows:ID, which renders the same frame with another shadow technique and
// prints the error against it: on a pane of stained glass `moment` is close to `reference`
// and `opaque` (which ignores the pane) is far from it; an unknown technique is one line.
#include "shadow_test_scenes.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() {
    const fs::path d = outputDir() / "shadow_cli";
    fs::create_directories(d);
    return d;
}

fs::path paneScene() {
    nlohmann::json doc = shadow_scenes::base({{"type", "opaque"}, {"size", 1024}});
    shadow_scenes::addPane(doc, "stained", 1.0, 1.0, {0.8, 0.5, 0.2});
    const fs::path p = dir() / "pane.json";
    std::ofstream(p) << doc.dump(1);
    return p;
}

nlohmann::json renderCompare(const std::string& shadows, const std::string& name) {
    const fs::path out = dir() / (name + ".exr"), report = dir() / (name + ".json");
    fs::remove(report);
    const CommandResult r =
        runCommand(veilExe() + " render '" + paneScene().string() + "' --width 64 --height 64 " +
                   "--shadows " + shadows + " --compare-to shadows:reference -o '" + out.string() +
                   "' --report '" + report.string() + "'");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("RMSE"), std::string::npos) << r.output;
    std::ifstream in(report);
    return nlohmann::json::parse(in);
}

} // namespace

TEST(ShadowCliTest, CompareToAShadowTechnique) {
    const nlohmann::json moment = renderCompare("moment", "moment");
    const nlohmann::json opaque = renderCompare("opaque", "opaque");
    EXPECT_EQ(moment["shadows"], "moment");
    // --shadows with another technique than the scene's: that technique's defaults (as --oit).
    EXPECT_EQ(moment["shadow_properties"]["size"], 2048);
    EXPECT_EQ(moment["shadow_lights"], nlohmann::json::array({0}));
    EXPECT_EQ(moment["compare"]["against"], "shadows:reference");
    // The pane's shadow covers about 1/16 of the image: `opaque` leaves it lit, an error of
    // (1 - T) x lit there; moment matches the exact product to its bias leak (< 0.5%) and
    // its filtered edges.
    const double om = opaque["compare"]["rmse"], mm = moment["compare"]["rmse"];
    EXPECT_GT(om, 0.02) << "opaque ignores the pane: its error is what the test measures";
    EXPECT_LT(mm, 0.25 * om) << "moment " << mm << " vs opaque " << om;
}

TEST(ShadowCliTest, UnknownShadowTechniqueIsOneLine) {
    const CommandResult r =
        runCommand(veilExe() + " render '" + paneScene().string() +
                   "' --compare-to shadows:nonesuch -o '" + (dir() / "x.png").string() + "'");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("unknown shadow technique 'nonesuch'"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "x.png"));
    const CommandResult s =
        runCommand(veilExe() + " render '" + paneScene().string() + "' --shadows nonesuch -o '" +
                   (dir() / "y.png").string() + "'");
    EXPECT_EQ(s.exitCode, 1) << s.output;
    EXPECT_NE(s.output.find("--shadows"), std::string::npos) << s.output;
}

} // namespace veil::test
