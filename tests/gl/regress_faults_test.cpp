// `veil regress` under faults, with real processes and signals: a run interrupted by SIGTERM
// leaves no report (neither the old nor a half-new one), no lock and no child behind and
// --resume completes it; a second run into the same folder is refused while the first holds
// it; SIGTERM to a --jobs parent ends its children and removes their .shard-N folders; a case
// whose process crashes (SIGSEGV) fails alone; a shard whose results.json points outside its
// folder is refused by --merge, which writes nothing; usage errors exit 2; a suite in a folder
// whose name is not UTF-8 gives a report.
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

extern char** environ;

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir() { return outputSubdir("regress-faults"); }

const char* kScene = R"({
  "render": {"width": 64, "height": 48, "oit": "blend"},
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
  "lights": [{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 2}],
  "materials": {"glass": {"base_color": 1, "alpha": 0.4}},
  "objects": [{"shape": {"type": "sphere", "radius": 0.5, "segments": 24, "rings": 12},
               "material": "glass"}]
})";

// `n` cases of the stochastic technique (4 seeds each) against `reference`.
fs::path prepare(const fs::path& d, int n) {
    fs::remove_all(d);
    fs::create_directories(d);
    writeTextFile(d / "scene.json", kScene);
    std::string cases;
    for (int i = 0; i < n; ++i)
        cases += std::string(i ? "," : "") + R"({"name": "c)" + std::to_string(i) +
                 R"(", "technique": {"type": "stochastic", "samples": 4}, "seeds": 4,
                 "metrics": {"rmse": 0.5}})";
    writeTextFile(d / "suite.json",
                  R"({"defaults": {"scene": "scene.json", "reference": "reference"},
                               "cases": [)" +
                      cases + "]}");
    return d / "suite.json";
}

// A veil process in the background, its output in `log`.
pid_t start(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<std::string> argv{veilExe()};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> c;
    for (std::string& a : argv)
        c.push_back(a.data());
    c.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = 0;
    EXPECT_EQ(posix_spawn(&pid, c[0], &fa, nullptr, c.data(), environ), 0);
    posix_spawn_file_actions_destroy(&fa);
    return pid;
}

int finish(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    return status;
}

bool waitUntil(const std::function<bool()>& done, double seconds = 60) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
}

// Pids of live processes whose command line holds `text`.
std::vector<pid_t> processesWith(const std::string& text) {
    std::vector<pid_t> out;
    for (const auto& e : fs::directory_iterator("/proc")) {
        const std::string name = e.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        std::string cmd = readTextFile(e.path() / "cmdline");
        std::replace(cmd.begin(), cmd.end(), '\0', ' ');
        if (cmd.find(text) != std::string::npos &&
            readTextFile(e.path() / "stat").find(") Z") == std::string::npos)
            out.push_back(std::stoi(name));
    }
    return out;
}

bool anyCaseFile(const fs::path& out) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out / "cases", ec))
        if (e.path().extension() == ".json") return true;
    return false;
}

int countTemporaries(const fs::path& d) {
    int n = 0;
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(d, ec))
        n += e.path().filename().string().find(".tmp") != std::string::npos;
    return n;
}

} // namespace

TEST(RegressFaultsTest, SigtermLeavesNoReportAndResumeCompletes) {
    const fs::path d = dir() / "sigterm";
    const fs::path s = prepare(d, 12), out = d / "out";
    // A finished report first: the interrupted run must not leave it beside its own images.
    ASSERT_EQ(
        runCommand(veilExe() + " regress " + shellQuote(s) + " -o " + shellQuote(out)).exitCode, 0);
    const pid_t pid = start({"regress", s.string(), "-o", out.string()}, d / "run.log");
    // Mid-run: the new run's worker is rendering a case and has finished one.
    ASSERT_TRUE(waitUntil([&] {
        return fs::exists(out / "cases" / ".running") && anyCaseFile(out) &&
               !fs::exists(out / "results.json");
    })) << readTextFile(d / "run.log");
    kill(pid, SIGTERM);
    const int status = finish(pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
    EXPECT_FALSE(fs::exists(out / "results.json"));
    EXPECT_FALSE(fs::exists(out / "index.html"));
    EXPECT_FALSE(fs::exists(out / ".veil-regress.lock"));
    EXPECT_EQ(countTemporaries(out), 0);
    EXPECT_TRUE(waitUntil([&] { return processesWith(out.string()).empty(); }, 10));
    // --resume keeps the finished cases and runs the rest.
    const CommandResult r =
        runCommand(veilExe() + " regress " + shellQuote(s) + " --resume -o " + shellQuote(out));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("12 of 12 cases passed"), std::string::npos) << r.output;
    EXPECT_EQ(nlohmann::json::parse(readTextFile(out / "results.json"))["cases"].size(), 12u);
}

TEST(RegressFaultsTest, SecondRunIntoTheSameFolderIsRefused) {
    const fs::path d = dir() / "concurrent";
    const fs::path s = prepare(d, 12), out = d / "out";
    const pid_t pid = start({"regress", s.string(), "-o", out.string()}, d / "first.log");
    ASSERT_TRUE(waitUntil([&] { return fs::exists(out / ".veil-regress.lock"); }));
    const CommandResult r =
        runCommand(veilExe() + " regress " + shellQuote(s) + " -o " + shellQuote(out));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("is in use by another veil regress (pid " + std::to_string(pid)),
              std::string::npos)
        << r.output;
    EXPECT_EQ(finish(pid), 0) << readTextFile(d / "first.log"); // the first run was not disturbed
    EXPECT_EQ(nlohmann::json::parse(readTextFile(out / "results.json"))["failed"], 0);
}

TEST(RegressFaultsTest, SigtermToJobsParentEndsChildrenAndShardFolders) {
    const fs::path d = dir() / "jobs";
    const fs::path s = prepare(d, 12), out = d / "out";
    const pid_t pid =
        start({"regress", s.string(), "--jobs", "2", "-o", out.string()}, d / "run.log");
    ASSERT_TRUE(waitUntil([&] { return anyCaseFile(out / ".shard-1"); }))
        << readTextFile(d / "run.log");
    kill(pid, SIGTERM);
    const int status = finish(pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
    EXPECT_TRUE(waitUntil([&] { return processesWith(out.string()).empty(); }, 10));
    // The children were ended, not left to finish their shards (12 cases in all).
    const std::string log = readTextFile(d / "run.log");
    std::size_t passed = 0;
    for (std::size_t p = log.find("PASS c"); p != std::string::npos; p = log.find("PASS c", p + 1))
        ++passed;
    EXPECT_LT(passed, 12u) << log;
    EXPECT_FALSE(fs::exists(out / ".shard-0"));
    EXPECT_FALSE(fs::exists(out / ".shard-1"));
    EXPECT_FALSE(fs::exists(out / ".veil-regress.lock"));
    EXPECT_FALSE(fs::exists(out / "results.json"));
}

TEST(RegressFaultsTest, CrashingCaseFailsThatCaseOnly) {
    const fs::path d = dir() / "crash";
    const fs::path s = prepare(d, 8), out = d / "out";
    const pid_t pid = start({"regress", s.string(), "-o", out.string()}, d / "run.log");
    std::vector<pid_t> worker;
    ASSERT_TRUE(waitUntil([&] {
        worker = processesWith("--worker");
        std::erase_if(worker, [&](pid_t p) {
            return readTextFile("/proc/" + std::to_string(p) + "/cmdline").find(out.string()) ==
                   std::string::npos;
        });
        return !worker.empty() && fs::exists(out / "cases" / ".running");
    })) << readTextFile(d / "run.log");
    kill(worker.front(), SIGSEGV);
    const int status = finish(pid);
    const std::string log = readTextFile(d / "run.log");
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << log;
    EXPECT_NE(log.find("crashed its process (signal 11"), std::string::npos) << log;
    const nlohmann::json j = nlohmann::json::parse(readTextFile(out / "results.json"));
    EXPECT_EQ(j["cases"].size(), 8u);
    EXPECT_EQ(j["failed"], 1) << log; // the other seven ran in a new process
}

TEST(RegressFaultsTest, MergeRefusesPathsOutsideTheShardAndWritesNothing) {
    const fs::path d = dir() / "traversal";
    const fs::path s = prepare(d, 2);
    ASSERT_EQ(runCommand(veilExe() + " regress " + shellQuote(s) + " -o " + shellQuote(d / "s0"))
                  .exitCode,
              0);
    writeTextFile(d / "victim.txt", "precious");
    nlohmann::json j = nlohmann::json::parse(readTextFile(d / "s0/results.json"));
    j["cases"][1]["render_png"] = "../victim.txt";
    writeTextFile(d / "s0/results.json", j.dump());
    fs::create_directories(d / "out");
    writeTextFile(d / "out/keep.txt", "x");
    const CommandResult r = runCommand(veilExe() + " regress " + shellQuote(s) + " --merge " +
                                       shellQuote(d / "s0") + " -o " + shellQuote(d / "out"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("'" + (d / "s0/results.json").string() +
                            "': case 'c1': render_png '../victim.txt' leaves the folder"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(readTextFile(d / "victim.txt"), "precious");
    EXPECT_FALSE(fs::exists(d / "out/images"));
    EXPECT_FALSE(fs::exists(d / "out/results.json"));
}

TEST(RegressFaultsTest, UsageErrorsExitTwo) {
    const fs::path d = dir() / "usage";
    const fs::path s = prepare(d, 1);
    for (const char* args :
         {" --shard a/b", " --shard 3/2", " --merge x --update", " --jobs 2 --shard 0/2",
          " --jobs 2 --merge x", " --resume --merge x", " --shard 0/2 --merge x"}) {
        const CommandResult r =
            runCommand(veilExe() + " regress " + shellQuote(s) + std::string(args));
        EXPECT_EQ(r.exitCode, 2) << args << ": " << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    }
}

TEST(RegressFaultsTest, FolderNameThatIsNotUtf8) {
    const fs::path d = dir() / "\xff\xfe-latin1-\xe9";
    const fs::path s = prepare(d, 1);
    const CommandResult r =
        runCommand(veilExe() + " regress " + shellQuote(s) + " -o " + shellQuote(d / "out"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(readTextFile(d / "out/results.json"));
    EXPECT_EQ(j["cases"].size(), 1u);
}

} // namespace veil::test
