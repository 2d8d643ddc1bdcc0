// The report folder of `veil regress` as one unit, and the shard folders it reads back
// (docs/regression.md "Report folders"):
// - every path taken from shard data resolves inside that shard's folder, every write inside
//   -o (safePathInside), case names are checked where they are read (checkCaseName);
// - results.json is written last and removed first, so a folder with results.json holds a
//   finished report and every reader (merge, --resume) checks for it;
// - one run at a time per folder (ReportLock: a lock file holding the pid);
// - per-case files written as each case ends, so a killed run resumes where it stopped.
#pragma once

#include "regress/report.h"

#include <filesystem>
#include <optional>
#include <string>

namespace veil::regress {

// Throws veil::Error unless `name` can name report files: letters, digits, '-', '_', '.', not
// empty, not starting with '.' (so not "." or "..").
void checkCaseName(const std::string& name, const std::string& where);
bool validCaseName(const std::string& name);

// `folder / relative` when `relative` is a relative path with no ".." and no "." component
// that, with symbolic links resolved, stays inside `folder`; else a veil::Error that starts
// with `what` (e.g. "'s0/results.json': case 'a': render_png").
std::filesystem::path safePathInside(const std::filesystem::path& folder,
                                     const std::string& relative, const std::string& what);

// The lock of a report folder: an fcntl write lock on `<dir>/.veil-regress.lock`, which holds
// the pid and host. A folder locked by a live process is a veil::Error naming the pid and the
// file; the kernel releases the lock when its process ends however it ends. The file is
// removed by the destructor, and on SIGINT/SIGTERM/SIGHUP by the regress command's signal
// handler (lockFileForSignals).
class ReportLock {
public:
    explicit ReportLock(const std::filesystem::path& dir);
    ~ReportLock();
    ReportLock(const ReportLock&) = delete;
    ReportLock& operator=(const ReportLock&) = delete;
    const std::filesystem::path& file() const { return file_; }

private:
    std::filesystem::path file_;
    int fd_ = -1;
};
// The lock file held now ("" when none), as a C string a signal handler may unlink.
const char* lockFileForSignals();

// `dir / name` as a real folder of `dir`, created when missing: a symbolic link there (which
// could lead the report's writes out of `dir`) or a file is a veil::Error naming it.
std::filesystem::path reportSubfolder(const std::filesystem::path& dir, const std::string& name);

// Removes the files of a previous report from `dir` (results.json first, then results.xml,
// index.html, cases/, images/); other files are left alone.
void clearReport(const std::filesystem::path& dir);

// cases/<name>.json with the suite's checksum and the binary's version, written atomically.
void writeCaseFile(const std::filesystem::path& dir, const CaseResult& c,
                   const std::string& suiteSha256, const std::string& version);
// The case file of `name` when it exists, is complete and was made from the same suite file
// and binary version; otherwise nothing (the case runs again).
std::optional<CaseResult> readCaseFile(const std::filesystem::path& dir, const std::string& name,
                                       const std::string& suiteSha256, const std::string& version);

// cases/.running: the case a worker process is rendering (for crash attribution).
void markRunning(const std::filesystem::path& dir, const std::string& name);
std::string runningCase(const std::filesystem::path& dir); // "" when none
void clearRunning(const std::filesystem::path& dir);

} // namespace veil::regress
