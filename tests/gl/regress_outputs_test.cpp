// What `veil regress` writes and where: a lock file that is a symbolic link (or a hard link)
// to a file outside -o is refused and the file is left alone; a suite that is a folder is named
// as one; a refused --merge leaves no -o behind and --merge never writes into the working
// folder; --resume with --jobs keeps the finished cases; --update creates a missing reference
// folder inside the suite's folder and refuses one outside it before rendering; each case's
// effective overrides are in its card, its JSON and its image headers, with the commit.
#include "io/image_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <map>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

const char* kScene = R"({
  "render": {"width": 32, "height": 24, "oit": "blend"},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
  "lights": [{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 2}],
  "materials": {"glass": {"base_color": 1, "alpha": 0.4}},
  "objects": [{"shape": {"type": "sphere", "radius": 0.5, "segments": 16, "rings": 8},
               "material": "glass"}]
})";

// A folder with scene.json and suite.json holding `cases` (a JSON array text).
fs::path suiteIn(const std::string& name, const std::string& cases) {
    const fs::path d = freshOutputDir("regress-outputs", name);
    writeTextFile(d / "scene.json", kScene);
    writeTextFile(d / "suite.json",
                  R"({"defaults": {"scene": "scene.json"}, "cases": )" + cases + "}");
    return d;
}

const char* kTwoCases = R"([
  {"name": "a", "reference": "blend", "metrics": {"rmse": 0.01}},
  {"name": "b", "reference": "blend", "overrides": ["render.background=0.25"],
   "metrics": {"rmse": 0.01}}])";

// The commit the veil binary names in --version (the test binary may be linked at another one
// when only veil was rebuilt).
std::string veilCommit() {
    const std::string v = runCommand(veilExe() + " --version").output;
    const auto at = v.find("(commit ");
    if (at == std::string::npos) return "(no commit in '" + v + "')";
    const auto from = at + 8;
    return v.substr(from, v.find_first_of(":)", from) - from);
}

CommandResult regress(const std::string& args) {
    return runCommand(veilExe() + " regress " + args);
}

void expectOneErrorLine(const CommandResult& r, const std::string& mustContain) {
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find("veil: error:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(mustContain), std::string::npos) << r.output;
}

} // namespace

TEST(RegressOutputsTest, LockFileLinkedOutsideIsRefusedAndLeftAlone) {
    const fs::path d = suiteIn("lock-link", kTwoCases);
    const fs::path victim = d / "victim.txt", out = d / "out";
    writeTextFile(victim, "keep me\n");
    fs::create_directories(out);
    fs::create_symlink(victim, out / ".veil-regress.lock");
    CommandResult r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(out));
    expectOneErrorLine(r, "symbolic link");
    EXPECT_NE(r.output.find(".veil-regress.lock"), std::string::npos) << r.output;
    EXPECT_EQ(readTextFile(victim), "keep me\n");
    EXPECT_TRUE(fs::is_symlink(out / ".veil-regress.lock"));
    EXPECT_FALSE(fs::exists(out / "results.json"));

    // A hard link to the file writes it as well: refused too.
    fs::remove(out / ".veil-regress.lock");
    fs::create_hard_link(victim, out / ".veil-regress.lock");
    r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(out));
    expectOneErrorLine(r, "not a regular file of its own");
    EXPECT_EQ(readTextFile(victim), "keep me\n");
}

TEST(RegressOutputsTest, ResumedCasesFolderLinkedOutsideIsRefused) {
    const fs::path d = suiteIn("cases-link", kTwoCases);
    const fs::path elsewhere = d / "elsewhere", out = d / "out";
    fs::create_directories(elsewhere);
    fs::create_directories(out);
    fs::create_directory_symlink(elsewhere, out / "cases");
    const CommandResult r =
        regress(shellQuote(d / "suite.json") + " -o " + shellQuote(out) + " --resume");
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("symbolic link"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_empty(elsewhere));
}

TEST(RegressOutputsTest, SuiteThatIsAFolderIsNamedAsOne) {
    const fs::path d = suiteIn("folder", kTwoCases);
    const CommandResult r = regress(shellQuote(d) + " -o " + shellQuote(d / "out"));
    expectOneErrorLine(r, "is a folder");
    EXPECT_NE(r.output.find("suite.json"), std::string::npos) << r.output; // the suggestion
    EXPECT_EQ(r.output.find("invalid JSON"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(RegressOutputsTest, RefusedMergeLeavesNothing) {
    const fs::path d = suiteIn("merge", kTwoCases);
    const fs::path work = d / "work";
    fs::create_directories(work);
    // A shard folder that holds no report: refused, and the new -o is not left behind.
    fs::create_directories(d / "s0");
    CommandResult r = runCommand("cd " + shellQuote(work) + " && " + veilExe() + " regress " +
                                 shellQuote(d / "suite.json") + " --merge " + shellQuote(d / "s0") +
                                 " -o " + shellQuote(d / "merged"));
    expectOneErrorLine(r, "results.json");
    EXPECT_FALSE(fs::exists(d / "merged"));
    // --merge without a shard folder before -o: a usage error, nothing written anywhere.
    r = runCommand("cd " + shellQuote(work) + " && " + veilExe() + " regress " +
                   shellQuote(d / "suite.json") + " --merge -o " + shellQuote(d / "merged"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(d / "merged"));
    EXPECT_TRUE(fs::is_empty(work)) << "no regress-report in the working folder";
}

TEST(RegressOutputsTest, ResumeWithJobsKeepsFinishedCases) {
    const fs::path d = suiteIn("resume-jobs", kTwoCases);
    const fs::path out = d / "out";
    CommandResult r =
        regress(shellQuote(d / "suite.json") + " -o " + shellQuote(out) + " --jobs 2");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json a = readJson(out / "cases" / "a.json");
    // As after an interrupted run: no results.json, case b not finished.
    fs::remove(out / "results.json");
    fs::remove(out / "cases" / "b.json");
    r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(out) + " --jobs 2 --resume");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // Case a was kept (its recorded time is the first run's), b ran again.
    EXPECT_EQ(readJson(out / "cases" / "a.json").value("seconds", -1.0), a.value("seconds", -2.0));
    EXPECT_TRUE(fs::exists(out / "cases" / "b.json"));
    const nlohmann::json results = readJson(out / "results.json");
    EXPECT_EQ(results.value("passed", 0), 2) << results.dump();
    ASSERT_EQ(results.value("cases", nlohmann::json::array()).size(), 2u) << results.dump();
    EXPECT_TRUE(fs::exists(out / results["cases"][0].value("render_png", "missing")));
}

TEST(RegressOutputsTest, UpdateCreatesTheReferenceFolderInsideTheSuiteFolderOnly) {
    const std::string commit = veilCommit();
    const fs::path d = suiteIn("update", R"([
      {"name": "a", "reference": "refs/new/a.exr", "metrics": {"rmse": 0}}])");
    CommandResult r =
        regress(shellQuote(d / "suite.json") + " -o " + shellQuote(d / "out") + " --update");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::is_regular_file(d / "refs" / "new" / "a.exr")) << r.output;
    EXPECT_NE(r.output.find("created reference folder"), std::string::npos) << r.output;
    // The stored reference records the case and its effective overrides.
    std::map<std::string, std::string> header;
    for (const auto& [k, v] : io::readImageAttributes(d / "refs" / "new" / "a.exr"))
        header[k] = v;
    EXPECT_EQ(header["veil:case"], "a");
    EXPECT_EQ(header["veil:commit"], commit);

    // A reference leaving the suite's folder: refused before anything renders or is created.
    const fs::path e = suiteIn("update-outside", R"([
      {"name": "a", "reference": "../outside-refs/a.exr", "metrics": {"rmse": 0}}])");
    r = regress(shellQuote(e / "suite.json") + " -o " + shellQuote(e / "out") + " --update");
    expectOneErrorLine(r, "leaves the folder");
    EXPECT_NE(r.output.find("/cases/0/reference"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(e.parent_path() / "outside-refs"));
    EXPECT_FALSE(fs::exists(e / "out"));
}

TEST(RegressOutputsTest, CaseOverridesAndCommitAreRecorded) {
    const std::string commit = veilCommit();
    const fs::path d = suiteIn("provenance", kTwoCases);
    const fs::path out = d / "out";
    const CommandResult r = regress(shellQuote(d / "suite.json") + " -o " + shellQuote(out));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json b = readJson(out / "cases" / "b.json");
    ASSERT_EQ(b.value("overrides", nlohmann::json()),
              nlohmann::json::array({"render.background=0.25"}))
        << b.dump();
    const std::string html = readTextFile(out / "index.html");
    EXPECT_NE(html.find("render.background=0.25"), std::string::npos);
    const nlohmann::json results = readJson(out / "results.json");
    EXPECT_EQ(results.value("veil_commit", ""), commit);
    EXPECT_NE(results.value("veil_version", "").find("commit " + commit), std::string::npos)
        << results.dump();
    EXPECT_NE(html.find("commit " + commit), std::string::npos);
    std::map<std::string, std::string> header;
    for (const auto& [k, v] : io::readImageAttributes(out / b.value("render_png", "missing")))
        header[k] = v;
    EXPECT_EQ(header["veil:commit"], commit);
    EXPECT_EQ(header["veil:case"], "b");
    EXPECT_EQ(nlohmann::json::parse(header["veil:overrides"]), b["overrides"]);
    // `veil --version` names the same commit.
    const CommandResult v = runCommand(veilExe() + " --version");
    EXPECT_NE(v.output.find("commit " + commit), std::string::npos) << v.output;
}

} // namespace veil::test
