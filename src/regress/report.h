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
    int failed() const;
};

// Writes cases/<name>.json, results.json, results.xml and index.html into `dir`.
void writeReport(const std::filesystem::path& dir, const Report& report);
// Reads <dir>/results.json (as writeReport wrote it); errors name the file.
Report readReport(const std::filesystem::path& dir);

} // namespace veil::regress
