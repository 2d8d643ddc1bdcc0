// The processes of one `veil regress` run (docs/regression.md "Interrupted and concurrent
// runs"): --jobs N runs N shards as child processes of this one and merges their folders; a
// shard's cases render in a worker process under a supervising one, started again after a
// case that crashed it (that case fails with the signal). SIGINT, SIGTERM and SIGHUP are
// passed on to the children (base/process.h); the parent removes what they left and its lock
// file, then dies of the same signal.
#pragma once

#include "regress/report.h"
#include "regress/runner.h"
#include "regress/suite.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace veil::regress {

// The command line children are started with: `<exe> regress <suite> --shard I/N -o DIR`,
// then --update and --device as given.
struct ChildCommand {
    std::string exe;   // the running veil binary
    std::string suite; // the suite file as given
    bool update = false;
    int device = -1; // -1: not passed
    bool resume = false;
};

// The forwarding handler (base/process.h) with the report lock file (lockFileForSignals)
// removed before the process dies; installed once.
void installSignalHandlers();

// Removes the previous report (regress::clearReport) with SIGINT/SIGTERM/SIGHUP held back,
// so a signal cannot leave part of it (an old index.html without its results.json).
void clearPreviousReport(const std::filesystem::path& out);

// --jobs N: N child processes with --shard i/N -o OUT/.shard-i; child k renders on the k-th
// allowed GPU mod their count (VEIL_GPU_SLOT, gpu/device_choice.h). Returns the shard
// folders, each holding a finished results.json; a shard that ended without one is a
// veil::Error naming how it ended (the folders are removed). A signal meanwhile removes them
// and ends the process. With command.resume, each shard folder starts with the case files
// (and images) of its cases that OUT holds from the same suite and `version`, and the children
// run with --resume.
std::vector<std::filesystem::path> runShardProcesses(const ChildCommand& command, int jobs,
                                                     const std::filesystem::path& out,
                                                     const Suite& suite,
                                                     const std::string& version);

// The shard's cases in a worker process (`--worker VERSION`), started again after a case that
// crashed it: that case's file says so and `onCase` gets it. Returns the device line the
// worker wrote (workerDeviceLine).
std::string superviseWorker(const ChildCommand& command, const Suite& suite, const Shard& shard,
                            const std::filesystem::path& out, const std::string& version,
                            const std::function<void(const CaseResult&)>& onCase);

// The worker's side: the device line ("EGL device I: renderer (version); chosen by ...") is
// printed and written to cases/.device, where superviseWorker reads it.
std::string workerDeviceLine(const gpu::ContextInfo& info, const std::filesystem::path& out);

} // namespace veil::regress
