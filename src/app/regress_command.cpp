// `veil regress suite.json`: renders every case of an image regression suite (one GL context,
// frame::Renderer as `veil render` uses it), compares each with its reference (a stored EXR,
// another technique, or the fog's CPU reference) by the case's metrics and tolerances, and
// writes per-case JSON, results.json, JUnit XML and an HTML report. The cases render in a
// worker process under this one, so a case that crashes its process fails that case and the
// shard goes on; the report folder is locked, results.json is written last, --resume keeps
// finished cases. Sharding (--shard I/N or the Slurm / Kubernetes array variables), --jobs
// (shards in child processes, merged) and --merge (shard folders into one report).
// docs/regression.md.
#include "app/commands.h"

#include "app/regress_processes.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/sha256.h"
#include "regress/report.h"
#include "regress/report_folder.h"
#include "regress/runner.h"
#include "regress/suite.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <signal.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

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
    bool resume = false;
    std::string worker; // hidden: render the shard's cases only; the value is the version
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

std::string exePath() { return fs::read_symlink("/proc/self/exe").string(); }

// The binary's identity in reports: its version and the start of its executable's SHA-256, so
// shards of two builds of one version are not merged.
std::string versionId() {
    return fmt::format("{} {}", VEIL_VERSION, sha256File(exePath()).substr(0, 12));
}

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Removes the previous report with SIGINT/SIGTERM/SIGHUP held back, so a signal cannot leave
// part of it (an old index.html without its results.json).
void clearPreviousReport(const fs::path& out) {
    sigset_t set, old;
    sigemptyset(&set);
    for (int sig : {SIGINT, SIGTERM, SIGHUP})
        sigaddset(&set, sig);
    sigprocmask(SIG_BLOCK, &set, &old);
    regress::clearReport(out);
    sigprocmask(SIG_SETMASK, &old, nullptr);
}

[[noreturn]] void usage(const std::string& option, const std::string& problem) {
    throw CLI::ValidationError(option, problem);
}

// --jobs N: N child processes `veil regress SUITE --shard i/N -o OUT/.shard-i`, merged. Child k
// renders on the k-th allowed GPU mod their count (VEIL_GPU_SLOT, gpu/device_choice.h).
std::vector<fs::path> runChildren(const RegressArgs& args, const fs::path& out) {
    const std::string exe = exePath();
    std::vector<pid_t> pids;
    std::vector<fs::path> dirs;
    for (int i = 0; i < args.jobs; ++i) {
        const fs::path dir = out / fmt::format(".shard-{}", i);
        std::error_code ec;
        fs::remove_all(dir, ec); // of an interrupted run
        dirs.push_back(dir);
    }
    auto removeDirs = [&] {
        std::error_code ec;
        for (const fs::path& d : dirs)
            fs::remove_all(d, ec);
    };
    for (int i = 0; i < args.jobs; ++i) {
        std::vector<std::string> argv{exe,
                                      "regress",
                                      args.suite,
                                      "--shard",
                                      fmt::format("{}/{}", i, args.jobs),
                                      "-o",
                                      dirs[static_cast<std::size_t>(i)].string()};
        if (args.update) argv.push_back("--update");
        if (args.device >= 0) argv.insert(argv.end(), {"--device", std::to_string(args.device)});
        pids.push_back(spawnChild(argv, {"VEIL_GPU_SLOT=" + std::to_string(i)}));
    }
    const std::vector<ChildExit> exits = waitChildren(pids);
    if (const int sig = pendingSignal()) {
        removeDirs();
        dieOfSignal(sig);
    }
    for (std::size_t i = 0; i < exits.size(); ++i) {
        // Exit status 1 with a results file is a shard with failing cases: merged below.
        if (fs::exists(dirs[i] / "results.json")) continue;
        const std::string how = exits[i].signal ? signalName(exits[i].signal)
                                                : fmt::format("status {}", exits[i].status);
        removeDirs();
        throw Error(fmt::format("--jobs: shard {} ended without results ({})", i, how));
    }
    return dirs;
}

// The shard's cases in a worker process, started again after a case that crashed it (that case
// fails with the signal); returns the device line the worker wrote.
std::string superviseWorker(const RegressArgs& args, const regress::Suite& suite,
                            const regress::Shard& shard, const fs::path& out,
                            const std::string& version) {
    regress::clearRunning(out);
    std::vector<std::string> argv{exePath(),
                                  "regress",
                                  args.suite,
                                  "--shard",
                                  fmt::format("{}/{}", shard.index, shard.count),
                                  "-o",
                                  out.string(),
                                  "--worker",
                                  version};
    if (args.update) argv.push_back("--update");
    if (args.device >= 0) argv.insert(argv.end(), {"--device", std::to_string(args.device)});
    const std::size_t cases = regress::shardCases(suite, shard).size();
    for (std::size_t attempt = 0; attempt <= cases; ++attempt) {
        const ChildExit e = waitChildren({spawnChild(argv, {})}).front();
        if (const int sig = pendingSignal()) dieOfSignal(sig);
        if (!e.signal && e.status == 0) return readText(out / "cases" / ".device");
        VEIL_CHECK(e.signal, "{}: the rendering process ended with status {} (its error is above)",
                   suite.file.string(), e.status);
        const std::string name = regress::runningCase(out);
        const regress::RegressCase* k = nullptr;
        for (const regress::RegressCase& c : suite.cases)
            if (c.name == name) k = &c;
        VEIL_CHECK(k, "{}: the rendering process died of {} outside a case", suite.file.string(),
                   signalName(e.signal));
        regress::CaseResult r;
        r.name = k->name;
        r.reference = k->referenceLabel();
        r.scene = k->scene.string();
        r.note = k->note;
        r.error = fmt::format("the case crashed its process ({}); the other cases ran in a new "
                              "process",
                              signalName(e.signal));
        regress::writeCaseFile(out, r, suite.sha256, version);
        regress::clearRunning(out);
        printCase(r);
    }
    throw Error(fmt::format("{}: the rendering process kept crashing", suite.file.string()));
}

void runWorker(const RegressArgs& args, const regress::Suite& suite, const regress::Shard& shard) {
    const fs::path out = args.output;
    regress::RunOptions options{out, args.update, args.device, printCase, args.worker, true, {}};
    options.onDevice = [&](const gpu::ContextInfo& info) {
        const std::string line =
            fmt::format("EGL device {}: {} ({}); chosen by {}", info.deviceIndex, info.renderer,
                        info.version, info.deviceChoice);
        std::cout << line << "\n";
        fs::create_directories(out / "cases");
        std::ofstream(out / "cases" / ".device") << line;
    };
    regress::runSuite(suite, options, shard);
}

void runRegress(const RegressArgs& args) {
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path out = args.output;
    // Usage errors (exit status 2).
    if (args.update && !args.merge.empty()) usage("--update", "cannot be combined with --merge");
    if (args.resume && !args.merge.empty()) usage("--resume", "cannot be combined with --merge");
    if (args.jobs != 1 && !(args.shard.empty() && args.merge.empty()))
        usage("--jobs", "cannot be combined with --shard or --merge");
    if (!args.shard.empty() && !args.merge.empty())
        usage("--shard", "cannot be combined with --merge");
    regress::Shard shard;
    if (args.merge.empty() && args.jobs == 1) {
        try {
            shard = regress::shardFromArgumentOrEnvironment(args.shard);
        } catch (const Error& e) {
            if (!args.shard.empty()) throw CLI::ValidationError(std::string(e.what()));
            throw;
        }
    }
    const regress::Suite suite = regress::loadSuite(args.suite, args.update);
    VEIL_CHECK(!fs::exists(out) || fs::is_directory(out), "output '{}' is not a folder",
               out.string());
    fs::create_directories(out);
    checkOutputPath(out / "results.json", "report", {suite.file});
    if (!args.worker.empty()) return runWorker(args, suite, shard);

    installRegressSignalHandlers();
    const regress::ReportLock lock(out);
    const std::string version = versionId();
    regress::Report report;
    if (!args.merge.empty()) {
        report = regress::mergeReports(suite, {args.merge.begin(), args.merge.end()}, out, version);
    } else if (args.jobs > 1) {
        if (!args.resume) clearPreviousReport(out);
        const std::vector<fs::path> dirs = runChildren(args, out);
        report = regress::mergeReports(suite, dirs, out, version);
        for (const fs::path& d : dirs)
            fs::remove_all(d);
    } else {
        std::cout << fmt::format("{}: {} of {} cases{}\n", suite.file.string(),
                                 regress::shardCases(suite, shard).size(), suite.cases.size(),
                                 shard.count > 1 ? " (shard " + shard.label() + ")" : "");
        std::cout.flush();
        // The previous report goes first (results.json first of all), or --resume keeps its
        // finished cases and only results.json goes.
        if (args.resume)
            fs::remove(out / "results.json");
        else
            clearPreviousReport(out);
        const std::string device = superviseWorker(args, suite, shard, out, version);
        // Every case now has its file: the report is made from them, nothing renders.
        regress::RunOptions options{out, false, args.device, {}, version, true, {}};
        report = regress::runSuite(suite, options, shard);
        report.device = device;
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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
        "regress", "Run an image regression suite (docs/regression.md); exit 0 only if all pass, "
                   "1 if a case failed or on an error, 2 on a usage error");
    cmd->add_option("suite", args->suite, "Suite file (JSON)")->required();
    cmd->add_option("-o,--output", args->output, "Report folder (default: regress-report)");
    cmd->add_flag("--update", args->update,
                  "Write the renders as the new stored references (cases with a .exr reference)");
    cmd->add_option("--shard", args->shard,
                    "Run only cases i with i % N == I (I/N; default from SLURM_ARRAY_TASK_ID / "
                    "SLURM_ARRAY_TASK_COUNT or JOB_COMPLETION_INDEX / VEIL_SHARD_COUNT)");
    cmd->add_flag("--resume", args->resume,
                  "Keep the cases a previous (interrupted) run into -o finished with the same "
                  "suite file and binary; run the others");
    cmd->add_option("--jobs", args->jobs,
                    "Run N shards in parallel child processes, merged (child k on GPU k mod G)")
        ->check(CLI::Range(1, 64));
    cmd->add_option("--merge", args->merge,
                    "Join the -o folders of shard runs into one report (no rendering)");
    cmd->add_option("--device", args->device,
                    "EGL device index (default: the GPU CUDA_VISIBLE_DEVICES / SLURM_STEP_GPUS / "
                    "SLURM_JOB_GPUS allow, else the first)")
        ->check(CLI::Range(0, 1023));
    cmd->add_option("--worker", args->worker)->group(""); // internal: the rendering process
    cmd->callback([args] { runRegress(*args); });
}

} // namespace veil::app
