// Running an image regression suite (docs/regression.md): every case rendered in one GL
// context with frame::Renderer as `veil render` uses it, compared with its reference (a stored
// EXR, another technique, or the fog's CPU reference) by the case's metrics and tolerances,
// with the report images written. Nothing here prints: callers get results (and a callback per
// case) and write the report with writeReport (regress/report.h).
#pragma once

#include "gpu/context.h"
#include "regress/report.h"
#include "regress/suite.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace veil::regress {

// Case i of a suite belongs to shard `index` of `count` when i % count == index.
struct Shard {
    int index = 0, count = 1;
    std::string label() const; // "I/N", or "" for the whole suite
};

// The shard of this run: `text` ("I/N", `veil regress --shard`) when not empty, else the array
// job variables SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT (counted from
// SLURM_ARRAY_TASK_MIN) or JOB_COMPLETION_INDEX / VEIL_SHARD_COUNT, else the whole suite.
// A malformed value is a veil::Error naming where it came from.
Shard shardFromArgumentOrEnvironment(const std::string& text);

// The cases of `suite` that `shard` runs, in suite order.
std::vector<const RegressCase*> shardCases(const Suite& suite, const Shard& shard);

struct RunOptions {
    std::filesystem::path output; // the report folder: images go to output/images
    bool update = false;          // write the renders as the new stored references
    int device = -1;              // EGL device index (-1: gpu/device_choice.h chooses)
    std::function<void(const CaseResult&)> onCase; // after each case (progress)
    // Each case's file (cases/<name>.json) is written as the case ends, with the suite's
    // checksum and this version; with `resume`, a case whose file is there from the same suite
    // and version is taken from it instead of rendered again.
    std::string version;
    bool resume = false;
    std::function<void(const gpu::ContextInfo&)> onDevice; // once the context exists
};

// One case in an existing context. Errors of the case (a scene that fails to render, a
// reference of another size) are its result (`error`), not exceptions.
CaseResult runCase(const RegressCase& k, const gpu::ContextInfo& info, const RunOptions& options);

// The cases of `shard` in one headless context (none is made when the shard is empty). The
// report is returned, not written.
Report runSuite(const Suite& suite, const RunOptions& options, const Shard& shard = {});

// Joins the report folders of shard runs into one report in suite order, copying their images
// into `out`; a case no folder ran is a failed case. Everything is checked before anything is
// written to `out`, and each problem is a veil::Error naming the shard's results.json (and the
// case): a folder without a finished report, a report of another suite file (checksum) or
// another `version`, a case in two folders or not in the suite, a bad case name, an image path
// that leaves its shard folder or is missing, `out` being one of the shard folders.
Report mergeReports(const Suite& suite, const std::vector<std::filesystem::path>& dirs,
                    const std::filesystem::path& out, const std::string& version = "");

} // namespace veil::regress
