// The outputs of `veil regress`: results.json (every case), results.xml (JUnit, for CI
// dashboards) and index.html (render / reference / heat map side by side with the numbers),
// all written atomically into the report folder.
#pragma once

#include "regress/suite.h"

#include <filesystem>
#include <string>
#include <vector>

namespace veil::regress {

struct Report {
    std::string suiteName;
    std::string suiteFile;
    std::string shard; // "I/N", or empty for a whole run or a merge
    std::vector<CaseResult> cases;
    double seconds = 0.0;
    std::string suiteSha256; // SHA-256 of the suite file's bytes
    std::string veilVersion; // the binary that ran it (merge refuses mixed ones)
    std::string device;      // the GL device and what chose it (empty for a merge)
    int failed() const;
};

// Writes cases/<name>.json, results.xml, index.html and, last, results.json into `dir` (a
// folder with results.json holds a finished report).
void writeReport(const std::filesystem::path& dir, const Report& report);
// Reads <dir>/results.json (as writeReport wrote it); errors name the file.
Report readReport(const std::filesystem::path& dir);

} // namespace veil::regress
