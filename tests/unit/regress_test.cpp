// The regression library (src/regress) called directly, without GL: suites are parsed and
// checked as a whole, shards split the cases, reports survive a write and a read, and merging
// shard folders finds missing, doubled and foreign cases.
#include "base/error.h"
#include "regress/report.h"
#include "regress/report_folder.h"
#include "regress/runner.h"
#include "regress/suite.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("regress-library"); }

const char* kScene = R"({
  "render": {"width": 16, "height": 12, "oit": "blend"},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
  "lights": [{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 2}],
  "materials": {"glass": {"base_color": 1, "alpha": 0.4}},
  "objects": [{"shape": {"type": "sphere", "radius": 0.5}, "material": "glass"}]
})";

// Writes the scene and `suite` into a folder of their own; returns the suite file.
fs::path suiteFile(const std::string& name, const std::string& suite) {
    const fs::path d = dir() / name;
    fs::create_directories(d);
    writeTextFile(d / "scene.json", kScene);
    writeTextFile(d / "suite.json", suite);
    return d / "suite.json";
}

std::string suiteError(const fs::path& suite) {
    return errorOf([&] { regress::loadSuite(suite, false); });
}

const char* kThreeCases = R"({
  "name": "three",
  "defaults": {"scene": "scene.json", "reference": "reference"},
  "cases": [
    {"name": "a", "technique": "blend", "metrics": {"rmse": 0.1}},
    {"name": "b", "technique": "wboit", "width": 8, "metrics": {"psnr": 20, "maxabs": 1}},
    {"name": "c", "technique": {"type": "stochastic", "samples": 4}, "seeds": 2,
     "metrics": {"rejected": 0.5}}
  ]
})";

regress::CaseResult result(const std::string& name, bool passed) {
    regress::CaseResult r;
    r.name = name;
    r.technique = "blend";
    r.reference = "reference";
    r.passed = passed;
    r.metrics.push_back({"rmse", 0.01, 0.1, true});
    r.metrics.push_back({"psnr", std::numeric_limits<double>::infinity(), 30.0, true});
    r.metrics.push_back({"maxabs", std::nan(""), 1.0, false});
    return r;
}

} // namespace

TEST(RegressLibraryTest, SuiteIsParsedWithDefaultsAndDerivedOverrides) {
    const regress::Suite suite = regress::loadSuite(suiteFile("parse", kThreeCases), false);
    EXPECT_EQ(suite.name, "three");
    ASSERT_EQ(suite.cases.size(), 3u);
    const regress::RegressCase& b = suite.cases[1];
    EXPECT_EQ(b.name, "b");
    EXPECT_EQ(b.technique, "wboit");
    EXPECT_EQ(b.reference, regress::ReferenceKind::Technique);
    EXPECT_EQ(b.referenceTechnique, "reference");
    EXPECT_EQ(b.scene.filename(), "scene.json");
    // Metrics in name order (JSON objects are read sorted).
    ASSERT_EQ(b.metrics.size(), 2u);
    EXPECT_EQ(b.metrics[0].first, "maxabs");
    EXPECT_EQ(b.metrics[1].first, "psnr");
    const std::vector<std::string> want{"render.oit=\"wboit\"", "render.width=8"};
    EXPECT_EQ(b.overrides, want);
    EXPECT_EQ(suite.cases[2].seeds, 2);
    EXPECT_EQ(suite.cases[2].technique, "stochastic");
}

TEST(RegressLibraryTest, BadSuitesNameTheFileAndJsonPointer) {
    const std::string unknown = suiteError(suiteFile("unknown-key", R"({"cases": [
        {"name": "a", "scene": "scene.json", "reference": "reference", "metrics": {"rmse": 1},
         "colour": 3}]})"));
    EXPECT_NE(unknown.find("suite.json: /cases/0/colour: unknown key"), std::string::npos)
        << unknown;
    const std::string twice = suiteError(suiteFile("twice", R"({"cases": [
        {"name": "a", "scene": "scene.json", "reference": "reference", "metrics": {"rmse": 1}},
        {"name": "a", "scene": "scene.json", "reference": "reference", "metrics": {"rmse": 1}}]})"));
    EXPECT_NE(twice.find("/cases/1/name: case name 'a' is used twice"), std::string::npos) << twice;
    const std::string stored = suiteError(suiteFile("stored", R"({"cases": [
        {"name": "a", "scene": "scene.json", "reference": "a.exr", "metrics": {"rmse": 1}}]})"));
    EXPECT_NE(stored.find("/cases/0/reference: reference image"), std::string::npos) << stored;
    EXPECT_NE(stored.find("--update writes it"), std::string::npos) << stored;
    // With update, a missing stored reference is what is about to be written.
    EXPECT_NO_THROW(regress::loadSuite(dir() / "stored" / "suite.json", true));
    const std::string cpu = suiteError(suiteFile("cpu", R"({"cases": [
        {"name": "a", "scene": "scene.json", "reference": "cpu", "metrics": {"rmse": 1}}]})"));
    EXPECT_NE(cpu.find("draws no surfaces"), std::string::npos) << cpu;
    const std::string rejected = suiteError(suiteFile("rejected", R"({"cases": [
        {"name": "a", "scene": "scene.json", "reference": "reference",
         "metrics": {"rejected": 0.1}}]})"));
    EXPECT_NE(rejected.find("needs \"seeds\" >= 2"), std::string::npos) << rejected;
}

TEST(RegressLibraryTest, ShardsSplitCasesByIndex) {
    const regress::Suite suite = regress::loadSuite(suiteFile("shards", kThreeCases), false);
    EXPECT_EQ(regress::shardCases(suite, {}).size(), 3u);
    const auto first = regress::shardCases(suite, {0, 2});
    ASSERT_EQ(first.size(), 2u);
    EXPECT_EQ(first[0]->name, "a");
    EXPECT_EQ(first[1]->name, "c");
    const auto second = regress::shardCases(suite, {1, 2});
    ASSERT_EQ(second.size(), 1u);
    EXPECT_EQ(second[0]->name, "b");
    EXPECT_EQ((regress::Shard{1, 2}).label(), "1/2");
    EXPECT_EQ(regress::Shard{}.label(), "");
}

TEST(RegressLibraryTest, ShardArgumentsAreChecked) {
    const regress::Shard s = regress::shardFromArgumentOrEnvironment("2/5");
    EXPECT_EQ(s.index, 2);
    EXPECT_EQ(s.count, 5);
    EXPECT_THROW(regress::shardFromArgumentOrEnvironment("2"), Error);
    EXPECT_THROW(regress::shardFromArgumentOrEnvironment("x/2"), Error);
    EXPECT_THROW(regress::shardFromArgumentOrEnvironment("2/2"), Error);
    EXPECT_THROW(regress::shardFromArgumentOrEnvironment("-1/2"), Error);
}

TEST(RegressLibraryTest, ShardComesFromArrayJobVariables) {
    ::setenv("JOB_COMPLETION_INDEX", "1", 1);
    ::setenv("VEIL_SHARD_COUNT", "4", 1);
    const regress::Shard s = regress::shardFromArgumentOrEnvironment("");
    EXPECT_EQ(s.index, 1);
    EXPECT_EQ(s.count, 4);
    // The argument wins over the environment.
    EXPECT_EQ(regress::shardFromArgumentOrEnvironment("0/2").count, 2);
    ::unsetenv("VEIL_SHARD_COUNT");
    EXPECT_THROW(regress::shardFromArgumentOrEnvironment(""), Error);
    ::unsetenv("JOB_COMPLETION_INDEX");
    EXPECT_EQ(regress::shardFromArgumentOrEnvironment("").count, 1);
}

TEST(RegressLibraryTest, ReportSurvivesWriteAndRead) {
    const fs::path d = dir() / "report";
    fs::remove_all(d);
    regress::Report r{
        "suite", "/x/suite.json", "0/2", {result("a", true), result("b", false)}, 1.5, "", "", ""};
    r.cases[1].error = "it broke";
    EXPECT_EQ(r.failed(), 1);
    regress::writeReport(d, r);
    for (const char* f : {"results.json", "results.xml", "index.html", "cases/a.json"})
        EXPECT_TRUE(fs::exists(d / f)) << f;
    const regress::Report back = regress::readReport(d);
    EXPECT_EQ(back.suiteName, "suite");
    EXPECT_EQ(back.shard, "0/2");
    EXPECT_EQ(back.seconds, 1.5);
    ASSERT_EQ(back.cases.size(), 2u);
    EXPECT_EQ(back.cases[1].error, "it broke");
    ASSERT_EQ(back.cases[0].metrics.size(), 3u);
    EXPECT_EQ(back.cases[0].metrics[0].value, 0.01);
    EXPECT_TRUE(std::isinf(back.cases[0].metrics[1].value)); // JSON has no infinity...
    EXPECT_TRUE(std::isnan(back.cases[0].metrics[2].value)); // ...nor NaN
    EXPECT_THROW(regress::readReport(dir() / "no-such-folder"), Error);
}

// A shard report of `suite` (its checksum recorded, as a run writes it).
regress::Report shardReport(const regress::Suite& suite, const std::string& shard,
                            std::vector<regress::CaseResult> cases, double seconds) {
    regress::Report r{"three", suite.file.string(), shard, std::move(cases), seconds, "", "", ""};
    r.suiteSha256 = suite.sha256;
    r.veilVersion = "v1";
    return r;
}

std::string mergeError(const regress::Suite& suite, const std::vector<fs::path>& dirs,
                       const fs::path& out) {
    try {
        regress::mergeReports(suite, dirs, out, "v1");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(RegressLibraryTest, MergeJoinsShardsInSuiteOrder) {
    const regress::Suite suite = regress::loadSuite(suiteFile("merge", kThreeCases), false);
    const fs::path d = dir() / "merge";
    for (const char* f : {"s0", "s1", "out", "dup", "foreign"})
        fs::remove_all(d / f);
    regress::writeReport(d / "s0",
                         shardReport(suite, "0/2", {result("c", true), result("a", true)}, 2));
    regress::Report s1 = shardReport(suite, "1/2", {result("b", false)}, 3);
    s1.cases[0].renderPng = "images/b-render.png";
    fs::create_directories(d / "s1" / "images");
    writeTextFile(d / "s1" / "images" / "b-render.png", "png");
    regress::writeReport(d / "s1", s1);

    const regress::Report merged =
        regress::mergeReports(suite, {d / "s0", d / "s1"}, d / "out", "v1");
    ASSERT_EQ(merged.cases.size(), 3u);
    EXPECT_EQ(merged.cases[0].name, "a");
    EXPECT_EQ(merged.cases[1].name, "b");
    EXPECT_EQ(merged.cases[2].name, "c");
    EXPECT_EQ(merged.failed(), 1);
    EXPECT_EQ(merged.seconds, 3); // the slowest shard
    EXPECT_TRUE(fs::exists(d / "out" / "images" / "b-render.png"));

    // A case no folder ran is a failed case.
    const regress::Report partial = regress::mergeReports(suite, {d / "s0"}, d / "out", "v1");
    EXPECT_EQ(partial.cases[1].error, "no merged shard ran this case");
    EXPECT_FALSE(partial.cases[1].passed);

    // The same case twice, or a case of another suite, is an error naming both files.
    regress::writeReport(d / "dup", shardReport(suite, "", {result("a", true)}, 1));
    EXPECT_NE(mergeError(suite, {d / "s0", d / "dup"}, d / "out")
                  .find("case 'a' is in two of the folders: '" + (d / "s0/results.json").string()),
              std::string::npos);
    regress::writeReport(d / "foreign", shardReport(suite, "", {result("zz", true)}, 1));
    EXPECT_NE(mergeError(suite, {d / "foreign"}, d / "out").find("case 'zz' is not in suite"),
              std::string::npos);
}

TEST(RegressLibraryTest, MergeRefusesShardsOfAnotherSuiteOrBinary) {
    const regress::Suite suite = regress::loadSuite(suiteFile("merge-other", kThreeCases), false);
    const fs::path d = dir() / "merge-other";
    for (const char* f : {"s0", "s1", "out"})
        fs::remove_all(d / f);
    regress::writeReport(d / "s0", shardReport(suite, "0/2", {result("a", true)}, 1));
    // The suite file changed (another tolerance) after shard 1 ran.
    regress::Report other = shardReport(suite, "1/2", {result("b", true)}, 1);
    other.suiteSha256 = std::string(64, 'f');
    regress::writeReport(d / "s1", other);
    std::string e = mergeError(suite, {d / "s0", d / "s1"}, d / "out");
    EXPECT_NE(e.find("'" + (d / "s1/results.json").string() + "' is a run of another suite file"),
              std::string::npos)
        << e;
    other.suiteSha256 = suite.sha256;
    other.veilVersion = "v2";
    regress::writeReport(d / "s1", other);
    e = mergeError(suite, {d / "s0", d / "s1"}, d / "out");
    EXPECT_NE(e.find("was made by another veil binary ('v2') than this one ('v1')"),
              std::string::npos)
        << e;
    EXPECT_FALSE(fs::exists(d / "out")); // a refused merge writes nothing
}

TEST(RegressLibraryTest, MergeKeepsEveryPathInsideItsFolder) {
    const regress::Suite suite = regress::loadSuite(suiteFile("merge-paths", kThreeCases), false);
    const fs::path d = dir() / "merge-paths";
    fs::remove_all(d / "s0");
    fs::remove_all(d / "out");
    fs::create_directories(d / "s0" / "images");
    writeTextFile(d / "victim.txt", "precious");
    writeTextFile(d / "s0" / "images" / "a-render.png", "png");
    fs::create_symlink(d / "victim.txt", d / "s0" / "images" / "link.png");
    // The previous report in -o must survive a refused merge.
    fs::create_directories(d / "out");
    writeTextFile(d / "out" / "results.json", "old");
    struct Bad {
        std::string png, expected;
    };
    const std::vector<Bad> bad{{"../victim.txt", "leaves the folder"},
                               {"images/../../victim.txt", "leaves the folder"},
                               {(d / "victim.txt").string(), "is not a path relative to"},
                               {"images/link.png", "outside the folder"},
                               {"images/none.png", "does not exist in"}};
    for (const Bad& b : bad) {
        regress::Report r = shardReport(suite, "", {result("a", true)}, 1);
        r.cases[0].renderPng = b.png;
        fs::remove(d / "s0" / "results.json");
        regress::writeReport(d / "s0", r);
        const std::string e = mergeError(suite, {d / "s0"}, d / "out");
        EXPECT_NE(e.find("'" + (d / "s0/results.json").string() + "': case 'a': render_png '" +
                         b.png + "'"),
                  std::string::npos)
            << e;
        EXPECT_NE(e.find(b.expected), std::string::npos) << e;
        EXPECT_FALSE(fs::exists(d / "out" / "images")) << b.png;
        EXPECT_EQ(readTextFile(d / "out" / "results.json"), "old");
        EXPECT_EQ(readTextFile(d / "victim.txt"), "precious");
    }
    // Case names that are not file names are refused where they are read.
    for (const char* name : {"..", ".", ".hidden", "a/b"}) {
        fs::remove(d / "s0" / "results.json");
        regress::writeReport(d / "s0", shardReport(suite, "", {}, 1));
        std::ifstream in(d / "s0" / "results.json");
        nlohmann::json j = nlohmann::json::parse(in);
        j["cases"].push_back(result(name, true).toJson());
        std::ofstream(d / "s0" / "results.json") << j.dump();
        EXPECT_NE(mergeError(suite, {d / "s0"}, d / "out").find("case name"), std::string::npos)
            << name;
    }
    // -o one of the shard folders (written with a trailing slash) is refused.
    regress::writeReport(d / "s0", shardReport(suite, "", {result("a", true)}, 1));
    EXPECT_NE(mergeError(suite, {d / "s0/"}, d / "s0").find("is one of the shard folders"),
              std::string::npos);
}

TEST(RegressLibraryTest, SuiteRefusesDotCaseNames) {
    for (const char* name : {".", "..", ".hidden"}) {
        const std::string suite = std::string(R"({"cases": [{"name": ")") + name +
                                  R"(", "scene": "scene.json", "reference": "reference",
                                  "metrics": {"rmse": 1}}]})";
        const std::string e = suiteError(suiteFile("dot-name", suite));
        EXPECT_NE(e.find("/cases/0/name: '" + std::string(name) + "': use letters"),
                  std::string::npos)
            << e;
    }
}

TEST(RegressLibraryTest, EveryReportFieldIsEscaped) {
    const fs::path d = dir() / "escape";
    fs::remove_all(d);
    const std::string evil = "<script>alert('x')</script>\"<img src=x onerror=alert(1)>&";
    regress::CaseResult c = result("a", false);
    c.technique = c.reference = c.scene = c.note = c.error = evil;
    c.renderPng = c.referencePng = c.diffPng = evil;
    c.metrics[0].name = evil;
    regress::Report r{evil, evil, evil, {c}, 1, "", "", ""};
    regress::writeReport(d, r);
    for (const char* f : {"index.html", "results.xml"}) {
        const std::string text = readTextFile(d / f);
        // The page's own script (one, after the last card) is the only one.
        const std::size_t script = text.find("<script");
        if (std::string(f) == "index.html") {
            ASSERT_NE(script, std::string::npos);
            const std::string own = "<script>\n(function () {";
            EXPECT_EQ(text.compare(script, own.size(), own), 0);
            EXPECT_EQ(text.find("<script", script + 1), std::string::npos) << f;
        } else {
            EXPECT_EQ(script, std::string::npos) << f;
        }
        EXPECT_EQ(text.find("<img src=x"), std::string::npos) << f;
        EXPECT_EQ(text.find("'x'"), std::string::npos) << f;
        EXPECT_NE(text.find("&lt;script&gt;alert(&apos;x&apos;)"), std::string::npos) << f;
    }
}

} // namespace veil::test
