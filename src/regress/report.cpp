#include "regress/report.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "io/provenance.h"
#include "regress/report_folder.h"
#include "regress/report_html.h"
#include "scene/json_text.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace veil::regress {

namespace fs = std::filesystem;

namespace {

nlohmann::json toJson(const Report& r) {
    nlohmann::json cases = nlohmann::json::array();
    for (const CaseResult& c : r.cases)
        cases.push_back(c.toJson());
    return {{"suite", r.suiteName},
            {"suite_file", r.suiteFile},
            {"shard", r.shard},
            {"suite_sha256", r.suiteSha256},
            {"veil_version", r.veilVersion},
            {"veil_commit", io::gitCommit()},
            {"device", r.device},
            {"cases", cases},
            {"passed", static_cast<int>(r.cases.size()) - r.failed()},
            {"failed", r.failed()},
            {"seconds", r.seconds}};
}

std::string junit(const Report& r) {
    std::ostringstream x;
    x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    x << fmt::format("<testsuites name=\"{}\" tests=\"{}\" failures=\"{}\" time=\"{:.3f}\">\n",
                     escapeMarkup(r.suiteName), r.cases.size(), r.failed(), r.seconds);
    x << fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" time=\"{:.3f}\">\n",
                     escapeMarkup(r.suiteName), r.cases.size(), r.failed(), r.seconds);
    for (const CaseResult& c : r.cases) {
        x << fmt::format("    <testcase classname=\"veil.regress\" name=\"{}\" time=\"{:.3f}\"",
                         escapeMarkup(c.name), c.seconds);
        std::string metricsText;
        for (const MetricResult& m : c.metrics)
            metricsText += fmt::format("{} {} (tolerance {}){}\n", m.name, reportNumber(m.value),
                                       reportNumber(m.threshold), m.passed ? "" : " FAILED");
        if (c.passed) {
            x << ">\n      <system-out>" << escapeMarkup(metricsText) << "</system-out>\n";
        } else {
            x << ">\n      <failure message=\"" << escapeMarkup(failureText(c)) << "\">"
              << escapeMarkup(metricsText) << "</failure>\n";
        }
        x << "    </testcase>\n";
    }
    x << "  </testsuite>\n</testsuites>\n";
    return x.str();
}

} // namespace

int Report::failed() const {
    int n = 0;
    for (const CaseResult& c : cases)
        n += !c.passed;
    return n;
}

void writeReport(const fs::path& dir, const Report& r) {
    for (const CaseResult& c : r.cases)
        writeCaseFile(dir, c, r.suiteSha256, r.veilVersion);
    writeTextFileAtomically(dir / "results.xml", junit(r));
    writeTextFileAtomically(dir / "index.html", reportHtml(r));
    // Paths in folders whose names are not UTF-8 are written with U+FFFD in their place.
    writeTextFileAtomically(
        dir / "results.json",
        toJson(r).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

Report readReport(const fs::path& dir) {
    const fs::path file = dir / "results.json";
    std::ifstream in(file);
    VEIL_CHECK(in, "cannot open '{}' (is '{}' the -o folder of a veil regress run?)", file.string(),
               dir.string());
    try {
        std::stringstream text;
        text << in.rdbuf();
        // The parser shared with scenes and suites (nesting cap, no duplicate keys).
        const nlohmann::json j = scene::parseJsonText(text.str(), file.string());
        Report r;
        r.suiteName = j.at("suite");
        r.suiteFile = j.at("suite_file");
        r.shard = j.at("shard");
        r.suiteSha256 = j.value("suite_sha256", "");
        r.veilVersion = j.value("veil_version", "");
        r.device = j.value("device", "");
        r.seconds = j.at("seconds");
        for (const auto& c : j.at("cases"))
            r.cases.push_back(CaseResult::fromJson(c));
        return r;
    } catch (const nlohmann::json::exception& e) {
        std::string what = e.what();
        if (const auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
        throw Error(fmt::format("'{}': not a veil regress results file: {}", file.string(), what));
    }
}

} // namespace veil::regress
