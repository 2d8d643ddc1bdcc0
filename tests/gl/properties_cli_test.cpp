// Technique properties through the veil command: `veil techniques`, --set render.oit.KEY and
// the report's effective values; a bad name or value is one line, exit 1 and no output file.
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() {
    const fs::path d = outputDir() / "properties_cli";
    fs::create_directories(d);
    return d;
}

std::string glassScene() { return (sourceDir() / "datasets/scenes/oit-glass.json").string(); }

CommandResult render(const std::string& extra, const fs::path& out, const fs::path& report) {
    fs::remove(out);
    fs::remove(report);
    return runCommand(veilExe() + " render '" + glassScene() + "' --width 64 --height 36 -o '" +
                      out.string() + "' --report '" + report.string() + "' " + extra);
}

} // namespace

TEST(PropertiesCliTest, TechniquesListsEveryTechniqueWithItsProperties) {
    const CommandResult r = runCommand(veilExe() + " techniques --json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('[')));
    std::vector<std::string> names;
    for (const auto& t : j) {
        names.push_back(t["kind"].get<std::string>() + " " + t["name"].get<std::string>());
        for (const auto& p : t["properties"]) {
            EXPECT_FALSE(p["doc"].get<std::string>().empty()) << t["name"] << p["key"];
            EXPECT_TRUE(p.contains("default") && p.contains("range") && p.contains("type"));
        }
    }
    for (const char* n : {"oit blend", "oit reference", "oit wboit", "oit phenomenological",
                          "oit moment-p6", "oit moment-t4-16", "oit stochastic-depth",
                          "oit phenomenological-volume", "shadows opaque"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    const CommandResult text = runCommand(veilExe() + " techniques moment-p6");
    ASSERT_EQ(text.exitCode, 0) << text.output;
    for (const char* s :
         {"overestimation", "bias", "5e-06", "[Munstermann18 sec. 3.2]", "available: yes"})
        EXPECT_NE(text.output.find(s), std::string::npos) << s << "\n" << text.output;
    const CommandResult bad = runCommand(veilExe() + " techniques nope");
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
    EXPECT_NE(bad.output.find("unknown technique 'nope'"), std::string::npos) << bad.output;
    const CommandResult shadow = runCommand(veilExe() + " techniques opaque");
    ASSERT_EQ(shadow.exitCode, 0) << shadow.output;
    for (const char* s : {"shadows opaque", "pcf_radius", "max_lights"})
        EXPECT_NE(shadow.output.find(s), std::string::npos) << s << "\n" << shadow.output;
}

TEST(PropertiesCliTest, SetReachesTheTechniqueAndTheReport) {
    const fs::path out = dir() / "stoch.png", report = dir() / "stoch.json";
    const CommandResult r = render(
        "--set render.oit.type=stochastic --set render.oit.samples=16 --set render.oit.passes=2",
        out, report);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(report);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["oit"], "stochastic");
    EXPECT_EQ(j["oit_properties"]["samples"], 16);
    EXPECT_EQ(j["oit_properties"]["passes"], 2);
    // The technique ran with them: 2 geometry passes (one per seed) were drawn.
    EXPECT_EQ(j["oit_stats"]["passes"], 2);
    EXPECT_EQ(j["oit_stats"]["geometry_passes"], 2);
}

TEST(PropertiesCliTest, BadPropertyIsOneLineAndNoOutput) {
    struct Case {
        const char* set;
        const char* expect;
    };
    const Case cases[] = {
        {"--set render.oit.type=stochastic --set render.oit.sample=16",
         "/render/oit/sample: unknown key of OIT technique 'stochastic' (accepted: samples, "
         "passes)"},
        {"--set render.oit.type=moment-p6 --set render.oit.bias=2",
         "/render/oit/bias: value 2 out of range [0, 0.999]"},
        {"--set render.oit.type=reference --set render.oit.max_pool_mib=big",
         "/render/oit/max_pool_mib: expected a number"},
        {"--set render.oit=nope", "/render/oit/type: unknown OIT technique 'nope'"},
        {"--set render.oit.type=blend --set render.oit.samples=4",
         "/render/oit/samples: unknown key of OIT technique 'blend' (accepted: none)"},
    };
    for (const Case& c : cases) {
        const fs::path out = dir() / "bad.png", report = dir() / "bad.json";
        const CommandResult r = render(c.set, out, report);
        EXPECT_EQ(r.exitCode, 1) << c.set << "\n" << r.output;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.set << "\n" << r.output;
        EXPECT_NE(r.output.find("oit-glass.json"), std::string::npos) << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.set;
        EXPECT_FALSE(fs::exists(report)) << c.set;
    }
}

} // namespace veil::test
