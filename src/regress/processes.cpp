// The processes of a regress run (processes.h).
#include "regress/processes.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/process.h"
#include "regress/report_folder.h"

#include <fmt/format.h>

#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

namespace veil::regress {

namespace fs = std::filesystem;

namespace {

extern "C" void removeLockFile() {
    if (const char* lock = lockFileForSignals(); lock[0]) ::unlink(lock);
}

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::vector<std::string> childArgv(const ChildCommand& command, const Shard& shard,
                                   const fs::path& out) {
    return {command.exe,
            "regress",
            command.suite,
            "--shard",
            fmt::format("{}/{}", shard.index, shard.count),
            "-o",
            out.string()};
}

void addOptions(const ChildCommand& command, std::vector<std::string>& argv) {
    if (command.update) argv.push_back("--update");
    if (command.device >= 0) argv.insert(argv.end(), {"--device", std::to_string(command.device)});
    if (command.resume) argv.push_back("--resume");
}

// --resume with --jobs: the finished cases of shard `shard` that `out` holds, copied into the
// shard's folder (case file and images) for the child's own --resume.
void seedShardFolder(const fs::path& out, const fs::path& dir, const Suite& suite,
                     const Shard& shard, const std::string& version) {
    for (const RegressCase* k : shardCases(suite, shard)) {
        const std::optional<CaseResult> done = readCaseFile(out, k->name, suite.sha256, version);
        if (!done) continue;
        for (const std::string* png : {&done->renderPng, &done->referencePng, &done->diffPng})
            if (!png->empty())
                fs::copy_file(safePathInside(out, *png, "--resume"),
                              reportSubfolder(dir, "images") / fs::path(*png).filename(),
                              fs::copy_options::overwrite_existing);
        writeCaseFile(dir, *done, suite.sha256, version);
    }
}

} // namespace

void installSignalHandlers() { process::forwardSignals(removeLockFile); }

void clearPreviousReport(const fs::path& out) {
    sigset_t set, old;
    sigemptyset(&set);
    for (int sig : {SIGINT, SIGTERM, SIGHUP})
        sigaddset(&set, sig);
    sigprocmask(SIG_BLOCK, &set, &old);
    clearReport(out);
    sigprocmask(SIG_SETMASK, &old, nullptr);
}

std::vector<fs::path> runShardProcesses(const ChildCommand& command, int jobs, const fs::path& out,
                                        const Suite& suite, const std::string& version) {
    std::vector<pid_t> pids;
    std::vector<fs::path> dirs;
    for (int i = 0; i < jobs; ++i) {
        const fs::path dir = out / fmt::format(".shard-{}", i);
        std::error_code ec;
        fs::remove_all(dir, ec); // of an interrupted run
        dirs.push_back(dir);
    }
    if (command.resume)
        for (int i = 0; i < jobs; ++i) {
            fs::create_directory(dirs[static_cast<std::size_t>(i)]);
            seedShardFolder(out, dirs[static_cast<std::size_t>(i)], suite, {i, jobs}, version);
        }
    auto removeDirs = [&] {
        std::error_code ec;
        for (const fs::path& d : dirs)
            fs::remove_all(d, ec);
    };
    for (int i = 0; i < jobs; ++i) {
        std::vector<std::string> argv =
            childArgv(command, {i, jobs}, dirs[static_cast<std::size_t>(i)]);
        addOptions(command, argv);
        pids.push_back(process::spawnChild(argv, {"VEIL_GPU_SLOT=" + std::to_string(i)}));
    }
    const std::vector<process::ChildExit> exits = process::waitChildren(pids);
    if (const int sig = process::pendingSignal()) {
        removeDirs();
        process::dieOfSignal(sig);
    }
    for (std::size_t i = 0; i < exits.size(); ++i) {
        // Exit status 1 with a results file is a shard with failing cases: merged by the caller.
        if (fs::exists(dirs[i] / "results.json")) continue;
        const std::string how = exits[i].signal ? process::signalName(exits[i].signal)
                                                : fmt::format("status {}", exits[i].status);
        removeDirs();
        throw Error(fmt::format("--jobs: shard {} ended without results ({})", i, how));
    }
    return dirs;
}

std::string superviseWorker(const ChildCommand& command, const Suite& suite, const Shard& shard,
                            const fs::path& out, const std::string& version,
                            const std::function<void(const CaseResult&)>& onCase) {
    clearRunning(out);
    std::vector<std::string> argv = childArgv(command, shard, out);
    argv.insert(argv.end(), {"--worker", version});
    addOptions(command, argv);
    const std::size_t cases = shardCases(suite, shard).size();
    for (std::size_t attempt = 0; attempt <= cases; ++attempt) {
        const process::ChildExit e = process::waitChildren({process::spawnChild(argv, {})}).front();
        if (const int sig = process::pendingSignal()) process::dieOfSignal(sig);
        if (!e.signal && e.status == 0) return readText(out / "cases" / ".device");
        VEIL_CHECK(e.signal, "{}: the rendering process ended with status {} (its error is above)",
                   suite.file.string(), e.status);
        const std::string name = runningCase(out);
        const RegressCase* k = nullptr;
        for (const RegressCase& c : suite.cases)
            if (c.name == name) k = &c;
        VEIL_CHECK(k, "{}: the rendering process died of {} outside a case", suite.file.string(),
                   process::signalName(e.signal));
        CaseResult r;
        r.name = k->name;
        r.reference = k->referenceLabel();
        r.scene = k->scene.string();
        r.note = k->note;
        r.overrides = k->overrides;
        r.error = fmt::format("the case crashed its process ({}); the other cases ran in a new "
                              "process",
                              process::signalName(e.signal));
        writeCaseFile(out, r, suite.sha256, version);
        clearRunning(out);
        if (onCase) onCase(r);
    }
    throw Error(fmt::format("{}: the rendering process kept crashing", suite.file.string()));
}

std::string workerDeviceLine(const gpu::ContextInfo& info, const fs::path& out) {
    const std::string line = fmt::format("EGL device {}: {} ({}); chosen by {}", info.deviceIndex,
                                         info.renderer, info.version, info.deviceChoice);
    std::cout << line << "\n";
    writeTextFileAtomically(reportSubfolder(out, "cases") / ".device", line);
    return line;
}

} // namespace veil::regress
