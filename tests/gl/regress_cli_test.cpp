// `veil regress` through the real binary on a small suite written here: sharded runs merged
// equal one unsharded run, a changed input fails and the report names the case, --update
// writes stored references, and every bad suite is one line naming the file and JSON path.
#include "io/image_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("regress-cli"); }

// A glass ball in front of a box: blend and reference differ a little, stochastic is noisy.
const char* kScene = R"({
  "render": {"width": 40, "height": 30, "oit": "blend"},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
  "lights": [{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 2}],
  "materials": {"m": {"base_color": 0.5}, "glass": {"base_color": 1, "alpha": 0.4},
                "red": {"base_color": [0.9, 0.1, 0.1], "alpha": 0.5}},
  "objects": [{"shape": {"type": "box", "size": [2, 1, 0.5]}, "material": "m"},
              {"shape": {"type": "sphere", "radius": 0.5, "segments": 16, "rings": 8},
               "material": "glass", "transform": {"translate": [0, 0.8, 1]}},
              {"shape": {"type": "sphere", "radius": 0.4, "segments": 16, "rings": 8},
               "material": "red", "transform": {"translate": [0.3, 0.7, 1.5]}}]
})";

// Five cases: a technique reference, a stored reference, a stochastic mean with the per-pixel
// test, the same scene with an override, and SSIM/PSNR bounds. Tolerances are loose here:
// these tests check the command, tests/regression/suite.json checks the renderer.
std::string suite(const std::string& extraOverride = "") {
    return std::string(R"({
  "name": "cli test suite",
  // comments are allowed
  "defaults": {"scene": "scene.json", "width": 40, "height": 30},
  "cases": [
    {"name": "blend", "technique": "blend", "reference": "reference",
     "metrics": {"rmse": 0.05, "maxabs": 1.0}},
    {"name": "stored", "technique": "reference", "reference": "stored.exr",
     "overrides": [)") +
           extraOverride + R"(],
     "metrics": {"maxabs": 0.002, "rmse": 0.0005}},
    {"name": "stochastic", "technique": {"type": "stochastic", "samples": 4}, "seeds": 3,
     "reference": "stochastic", "reference_seeds": 3, "reference_properties": {"samples": 4},
     "metrics": {"rejected": 0.5, "rmse": 0.2}},
    {"name": "wide", "technique": "wboit", "reference": "reference", "width": 32, "height": 20,
     "metrics": {"ssim": 0.5, "psnr": 10}},
    {"name": "exposure", "technique": "blend", "reference": "reference",
     "overrides": ["render.exposure=2"], "metrics": {"p99": 1.0, "relmse": 1.0}}
  ]
})";
}

CommandResult regress(const std::string& args, const std::string& env = "") {
    return runCommand(env + " " + veilExe() + " regress " + args);
}

// Metric values by case name from a results.json.
std::map<std::string, nlohmann::json> metricsOf(const fs::path& report) {
    const nlohmann::json j = nlohmann::json::parse(readTextFile(report / "results.json"));
    std::map<std::string, nlohmann::json> m;
    for (const auto& c : j["cases"])
        m[c["name"]] = c["metrics"];
    return m;
}

// Writes the scene and a suite into `d` and creates its stored reference.
fs::path prepare(const fs::path& d) {
    fs::remove_all(d);
    fs::create_directories(d);
    writeTextFile(d / "scene.json", kScene);
    writeTextFile(d / "suite.json", suite());
    const CommandResult r =
        regress(shellQuote(d / "suite.json") + " --update -o " + shellQuote(d / "update"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return d / "suite.json";
}

} // namespace

TEST(RegressCliTest, UpdateCreatesStoredReferencesThenRunsPass) {
    const fs::path d = dir() / "update";
    fs::remove_all(d);
    fs::create_directories(d);
    writeTextFile(d / "scene.json", kScene);
    writeTextFile(d / "suite.json", suite());
    // Without the stored reference the suite is refused before rendering.
    CommandResult r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(d / "out"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("/cases/1/reference: reference image"), std::string::npos) << r.output;
    r = regress(shellQuote(d / "suite.json") + " --update -o " + shellQuote(d / "out"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("updated " + (d / "stored.exr").string() + " (created)"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(io::readImage(d / "stored.exr").width, 40);
    r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(d / "out"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("5 of 5 cases passed"), std::string::npos) << r.output;
    // A second update reports what changed: nothing.
    r = regress(shellQuote(d / "suite.json") + " --update -o " + shellQuote(d / "out"));
    EXPECT_NE(r.output.find("rmse 0, max-abs 0 against the old one"), std::string::npos)
        << r.output;
    for (const char* f :
         {"results.json", "results.xml", "index.html", "cases/stored.json",
          "images/stored-render.png", "images/stored-reference.png", "images/stored-diff.png"})
        EXPECT_TRUE(fs::exists(d / "out" / f)) << f;
    const std::string xml = readTextFile(d / "out/results.xml");
    EXPECT_NE(xml.find("<testsuites name=\"cli test suite\" tests=\"5\" failures=\"0\""),
              std::string::npos)
        << xml;
}

TEST(RegressCliTest, ShardsMergedEqualOneUnshardedRun) {
    const fs::path d = dir() / "shards";
    const fs::path s = prepare(d);
    CommandResult r = regress(shellQuote(s) + " -o " + shellQuote(d / "all"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // Shards 0 and 2 by option, shard 1 through the Slurm array variables (ids from 1).
    r = regress(shellQuote(s) + " --shard 0/3 -o " + shellQuote(d / "s0"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("2 of 5 cases (shard 0/3)"), std::string::npos) << r.output;
    r = regress(shellQuote(s) + " -o " + shellQuote(d / "s1"),
                "SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=3");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("2 of 5 cases (shard 1/3)"), std::string::npos) << r.output;
    r = regress(shellQuote(s) + " -o " + shellQuote(d / "s2"),
                "JOB_COMPLETION_INDEX=2 VEIL_SHARD_COUNT=3");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("1 of 5 cases (shard 2/3)"), std::string::npos) << r.output;
    r = regress(shellQuote(s) + " --merge " + shellQuote(d / "s0") + " " + shellQuote(d / "s1") +
                " " + shellQuote(d / "s2") + " -o " + shellQuote(d / "merged"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto all = metricsOf(d / "all"), merged = metricsOf(d / "merged");
    EXPECT_EQ(all.size(), 5u);
    EXPECT_EQ(all, merged);
    EXPECT_TRUE(fs::exists(d / "merged/images/wide-diff.png"));
    // --jobs runs the shards as child processes and merges them the same way.
    r = regress(shellQuote(s) + " --jobs 3 -o " + shellQuote(d / "jobs"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(metricsOf(d / "jobs"), all);
    // A merge that misses a shard fails and names the cases no shard ran.
    r = regress(shellQuote(s) + " --merge " + shellQuote(d / "s0") + " " + shellQuote(d / "s1") +
                " -o " + shellQuote(d / "part"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    // Case 2 (stochastic) was shard 2's.
    EXPECT_NE(r.output.find("1 case(s) failed: stochastic"), std::string::npos) << r.output;
    EXPECT_NE(readTextFile(d / "part/index.html").find("no merged shard ran this case"),
              std::string::npos);
}

TEST(RegressCliTest, ChangedInputFailsAndTheReportNamesTheCase) {
    const fs::path d = dir() / "changed";
    prepare(d);
    // The light twice as bright: the stored reference no longer matches.
    writeTextFile(d / "suite.json", suite(R"("lights.0.intensity=4")"));
    CommandResult r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(d / "out"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("FAIL stored"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 case(s) failed: stored"), std::string::npos) << r.output;
    const std::string html = readTextFile(d / "out/index.html");
    EXPECT_NE(html.find("Failed cases"), std::string::npos);
    EXPECT_NE(html.find("<a href=\"#stored\">stored</a>: maxabs"), std::string::npos) << html;
    EXPECT_NE(readTextFile(d / "out/results.xml").find("<failure message=\"maxabs"),
              std::string::npos);
    // A modified stored reference fails the same way.
    writeTextFile(d / "suite.json", suite());
    ImageF ref = io::readImage(d / "stored.exr");
    ref.at(5, 5, 0) += 0.5f;
    io::writeImage(d / "stored.exr", ref);
    r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(d / "out2"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(readTextFile(d / "out2/index.html").find("<a href=\"#stored\">stored</a>"),
              std::string::npos);
}

TEST(RegressCliTest, BadSuitesAreOneLineNamingFileAndPointer) {
    const fs::path d = dir() / "bad";
    fs::create_directories(d);
    writeTextFile(d / "scene.json", kScene);
    struct Bad {
        std::string text, expected;
    };
    const std::string ok = R"("name": "a", "scene": "scene.json", "reference": "reference")";
    const std::vector<Bad> bad{
        {"{\"cases\": [{" + ok + ", \"metrics\": {\"rmse\": -1}}]}",
         "/cases/0/metrics/rmse: tolerance -1 must be >= 0"},
        {"{\"cases\": [{" + ok + ", \"metrics\": {\"ssim\": 2}}]}", "/cases/0/metrics/ssim"},
        {"{\"cases\": [{" + ok + ", \"metrics\": {\"mse\": 1}}]}",
         "/cases/0/metrics/mse: unknown metric"},
        {"{\"cases\": [{" + ok + ", \"metrics\": {\"rmse\": \"small\"}}]}",
         "/cases/0/metrics/rmse: expected a number"},
        {"{\"cases\": [{" + ok + ", \"metric\": {\"rmse\": 1}}]}", "/cases/0/metric: unknown key"},
        {"{\"cases\": [{\"name\": \"a\", \"scene\": \"nope.json\", \"reference\": \"reference\", "
         "\"metrics\": {\"rmse\": 1}}]}",
         "/cases/0/scene: scene file"},
        {"{\"cases\": [{" + ok + ", \"metrics\": {\"rejected\": 0.1}}]}",
         "/cases/0/metrics/rejected: the per-pixel test needs"},
        {"{\"cases\": [{" + ok + ", \"technique\": \"nope\", \"metrics\": {\"rmse\": 1}}]}",
         "/cases/0/technique: unknown OIT technique 'nope'"},
        {"{\"cases\": [{" + ok +
             ", \"overrides\": [\"render.width=wide\"], \"metrics\": "
             "{\"rmse\": 1}}]}",
         "/cases/0/scene: "},
        {"{\"cases\": [{" + ok + ", \"width\": 0, \"metrics\": {\"rmse\": 1}}]}",
         "/cases/0/width: value 0 out of range"},
        {"{\"cases\": [{\"name\": \"a\", \"scene\": \"scene.json\", \"reference\": \"cpu\", "
         "\"metrics\": {\"rmse\": 1}}]}",
         "/cases/0/reference: the CPU fog reference draws no surfaces"},
        {"{\"cases\": [{" + ok + ", \"metrics\": {\"rmse\": 1}}, {" + ok +
             ", \"metrics\": {\"rmse\": 1}}]}",
         "/cases/1/name: case name 'a' is used twice"},
        {"{\"cases\": []}", "/cases: expected a non-empty array"},
        {"{\"cases\": [", "invalid JSON"},
        {"{\"case\": []}", "/case: unknown key"},
    };
    for (std::size_t i = 0; i < bad.size(); ++i) {
        const fs::path s = d / ("bad" + std::to_string(i) + ".json");
        writeTextFile(s, bad[i].text);
        const CommandResult r = regress(shellQuote(s) + " -o " + shellQuote(d / "out"));
        EXPECT_EQ(r.exitCode, 1) << bad[i].text << "\n" << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_NE(r.output.find("veil: error: " + s.string() + ": "), std::string::npos)
            << r.output;
        EXPECT_NE(r.output.find(bad[i].expected), std::string::npos) << bad[i].text << "\n"
                                                                     << r.output;
    }
    const CommandResult r = regress(shellQuote(d / "missing-suite.json"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("missing-suite.json"), std::string::npos) << r.output;
    EXPECT_NE(regress(shellQuote(d / "bad0.json") + " --shard 3/3").exitCode, 0);
}

} // namespace veil::test
