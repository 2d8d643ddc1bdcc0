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

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/sha256.h"
#include "io/provenance.h"
#include "regress/processes.h"
#include "regress/report.h"
#include "regress/report_folder.h"
#include "regress/runner.h"
#include "regress/suite.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <iostream>
#include <memory>

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

// The binary's identity in reports: its version and commit (io/provenance.h) and the start of
// its executable's SHA-256, so shards of two builds of one commit are not merged either.
std::string versionId() {
    return fmt::format("{}, binary sha256 {}", io::versionLine(),
                       sha256File(exePath()).substr(0, 12));
}

// Creates the folder when it does not exist; the destructor removes it again when it is still
// empty (a refused run: the lock file, removed first, was all it held).
class CreatedFolder {
public:
    explicit CreatedFolder(const fs::path& dir) : dir_(dir) {
        std::error_code ec;
        if (fs::exists(dir, ec)) return;
        fs::create_directories(dir);
        created_ = true;
    }
    ~CreatedFolder() {
        std::error_code ec;
        if (created_ && fs::is_empty(dir_, ec) && !ec) fs::remove(dir_, ec);
    }
    CreatedFolder(const CreatedFolder&) = delete;
    CreatedFolder& operator=(const CreatedFolder&) = delete;

private:
    fs::path dir_;
    bool created_ = false;
};

[[noreturn]] void usage(const std::string& option, const std::string& problem) {
    throw CLI::ValidationError(option, problem);
}

regress::ChildCommand childCommand(const RegressArgs& args) {
    return {exePath(), args.suite, args.update, args.device, args.resume};
}

void runWorker(const RegressArgs& args, const regress::Suite& suite, const regress::Shard& shard) {
    const fs::path out = args.output;
    regress::RunOptions options{out, args.update, args.device, printCase, args.worker, true, {}};
    options.onDevice = [&](const gpu::ContextInfo& info) { regress::workerDeviceLine(info, out); };
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
    // CLI11 takes the word after --merge as a folder even when it is an option: `--merge -o out`
    // would merge folders '-o' and 'out' into ./regress-report.
    for (const std::string& d : args.merge)
        if (!d.empty() && d[0] == '-')
            usage("--merge", fmt::format("'{}' is not a shard folder: give the folders after "
                                         "--merge, other options before it (veil regress "
                                         "suite.json -o out --merge shard0 shard1)",
                                         d));
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
    if (!args.worker.empty()) return runWorker(args, suite, shard);
    // A run refused before it wrote its report leaves no -o folder it created.
    const CreatedFolder created(out);
    checkOutputPath(out / "results.json", "report", {suite.file});

    regress::installSignalHandlers();
    const regress::ReportLock lock(out);
    if (args.resume) // the folders --resume keeps must not lead the writes out of -o
        for (const char* sub : {"cases", "images"})
            regress::reportSubfolder(out, sub);
    if (args.update) // every reference path checked, its folders made, before rendering
        for (const fs::path& d : regress::prepareReferenceFolders(suite))
            std::cout << "created reference folder " << d.string() << "\n";
    const std::string version = versionId();
    regress::Report report;
    if (!args.merge.empty()) {
        report = regress::mergeReports(suite, {args.merge.begin(), args.merge.end()}, out, version);
    } else if (args.jobs > 1) {
        if (!args.resume) regress::clearPreviousReport(out);
        const std::vector<fs::path> dirs =
            regress::runShardProcesses(childCommand(args), args.jobs, out, suite, version);
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
            regress::clearPreviousReport(out);
        const std::string device =
            regress::superviseWorker(childCommand(args), suite, shard, out, version, printCase);
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
