// `veil regress suite.json`: renders every case of an image regression suite in this process
// (one GL context, frame::Renderer as `veil render` uses it), compares each with its
// reference (a stored EXR, another technique, or the fog's CPU reference) by the case's
// metrics and tolerances, and writes per-case JSON, results.json, JUnit XML and an HTML
// report. Sharding (--shard I/N or the Slurm / Kubernetes array variables), --jobs (shards
// in child processes, merged) and --merge (shard folders into one report). docs/regression.md.
#include "app/commands.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "regress/report.h"
#include "regress/runner.h"
#include "regress/suite.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <iostream>
#include <memory>

extern char** environ;

namespace veil::app {

namespace fs = std::filesystem;

namespace {

struct RegressArgs {
    std::string suite;
    std::string output = "regress-report";
    std::string shard;
    std::vector<std::string> merge;
    int jobs = 1;
    int device = -1;
    bool update = false;
};

void printCase(const regress::CaseResult& r) {
    if (!r.updated.empty()) std::cout << "  updated " << r.updated << "\n";
    std::string m;
    for (const regress::MetricResult& x : r.metrics)
        m += fmt::format("{}{} {:.4g}{}", m.empty() ? "" : ", ", x.name, x.value,
                         x.passed ? "" : fmt::format(" (tolerance {:.4g})", x.threshold));
    std::cout << fmt::format("{} {} ({} vs {}): {} ({:.1f} s)\n", r.passed ? "PASS" : "FAIL",
                             r.name, r.technique, r.reference, r.error.empty() ? m : r.error,
                             r.seconds);
    std::cout.flush();
}

// --jobs N: N child processes `veil regress SUITE --shard i/N -o OUT/.shard-i`, merged.
std::vector<fs::path> runChildren(const RegressArgs& args, const fs::path& out) {
    const std::string exe = fs::read_symlink("/proc/self/exe").string();
    std::vector<pid_t> pids;
    std::vector<fs::path> dirs;
    for (int i = 0; i < args.jobs; ++i) {
        const fs::path dir = out / fmt::format(".shard-{}", i);
        dirs.push_back(dir);
        std::vector<std::string> argv{
            exe,  "regress",   args.suite, "--shard", fmt::format("{}/{}", i, args.jobs),
            "-o", dir.string()};
        if (args.update) argv.push_back("--update");
        if (args.device >= 0) argv.insert(argv.end(), {"--device", std::to_string(args.device)});
        std::vector<char*> cargv;
        for (std::string& a : argv)
            cargv.push_back(a.data());
        cargv.push_back(nullptr);
        pid_t pid = 0;
        const int rc = posix_spawn(&pid, exe.c_str(), nullptr, nullptr, cargv.data(), environ);
        VEIL_CHECK(rc == 0, "--jobs: cannot start '{}': {}", exe, std::strerror(rc));
        pids.push_back(pid);
    }
    for (std::size_t i = 0; i < pids.size(); ++i) {
        int status = 0;
        waitpid(pids[i], &status, 0);
        // Exit status 1 with a results file is a shard with failing cases: merged below.
        VEIL_CHECK(fs::exists(dirs[i] / "results.json"),
                   "--jobs: shard {} ended without results (status {})", i, status);
    }
    return dirs;
}

void runRegress(const RegressArgs& args) {
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path out = args.output;
    VEIL_CHECK(!(args.update && !args.merge.empty()), "--update cannot be combined with --merge");
    VEIL_CHECK(args.jobs == 1 || (args.shard.empty() && args.merge.empty()),
               "--jobs cannot be combined with --shard or --merge");
    const regress::Suite suite = regress::loadSuite(args.suite, args.update);
    VEIL_CHECK(!fs::exists(out) || fs::is_directory(out), "output '{}' is not a folder",
               out.string());
    fs::create_directories(out);
    checkOutputPath(out / "results.json", "report", {suite.file});

    regress::Report report;
    if (!args.merge.empty()) {
        report = regress::mergeReports(suite, {args.merge.begin(), args.merge.end()}, out);
    } else if (args.jobs > 1) {
        const std::vector<fs::path> dirs = runChildren(args, out);
        report = regress::mergeReports(suite, dirs, out);
        for (const fs::path& d : dirs)
            fs::remove_all(d);
        report.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    } else {
        const regress::Shard shard = regress::shardFromArgumentOrEnvironment(args.shard);
        std::cout << fmt::format("{}: {} of {} cases{}\n", suite.file.string(),
                                 regress::shardCases(suite, shard).size(), suite.cases.size(),
                                 shard.count > 1 ? " (shard " + shard.label() + ")" : "");
        regress::RunOptions options{out, args.update, args.device, printCase};
        report = regress::runSuite(suite, options, shard);
        report.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    regress::writeReport(out, report);
    const int failed = report.failed();
    std::cout << fmt::format("{} of {} cases passed ({:.1f} s); report {}\n",
                             report.cases.size() - failed, report.cases.size(), report.seconds,
                             (out / "index.html").string());
    if (failed) {
        std::vector<std::string> names;
        for (const regress::CaseResult& c : report.cases)
            if (!c.passed) names.push_back(c.name);
        throw Error(fmt::format("{}: {} case(s) failed: {}; see {}", suite.file.string(), failed,
                                fmt::join(names, ", "), (out / "index.html").string()));
    }
}

} // namespace

void addRegressCommand(CLI::App& app) {
    auto args = std::make_shared<RegressArgs>();
    CLI::App* cmd = app.add_subcommand(
        "regress", "Run an image regression suite (docs/regression.md); exit 0 only if all pass");
    cmd->add_option("suite", args->suite, "Suite file (JSON)")->required();
    cmd->add_option("-o,--output", args->output, "Report folder (default: regress-report)");
    cmd->add_flag("--update", args->update,
                  "Write the renders as the new stored references (cases with a .exr reference)");
    cmd->add_option("--shard", args->shard,
                    "Run only cases i with i % N == I (I/N; default from SLURM_ARRAY_TASK_ID / "
                    "SLURM_ARRAY_TASK_COUNT or JOB_COMPLETION_INDEX / VEIL_SHARD_COUNT)");
    cmd->add_option("--jobs", args->jobs, "Run N shards in parallel child processes, merged")
        ->check(CLI::Range(1, 64));
    cmd->add_option("--merge", args->merge,
                    "Join the -o folders of shard runs into one report (no rendering)");
    cmd->add_option("--device", args->device, "EGL device index")->check(CLI::Range(0, 1023));
    cmd->callback([args] { runRegress(*args); });
}

} // namespace veil::app
