#include "regress/report.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "regress/report_folder.h"
#include "scene/json_text.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace veil::regress {

namespace fs = std::filesystem;

namespace {

std::string escape(const std::string& s) { // HTML and XML text and attributes
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        case '\'':
            out += "&apos;";
            break;
        default:
            // XML 1.0 allows no control characters but tab, newline and carriage return.
            if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r')
                out += '?';
            else
                out += c;
        }
    }
    return out;
}

std::string num(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return fmt::format("{:.5g}", v);
}

std::string failureText(const CaseResult& c) {
    if (!c.error.empty()) return c.error;
    std::string s;
    for (const MetricResult& m : c.metrics)
        if (!m.passed)
            s += fmt::format("{}{} {} {} {}", s.empty() ? "" : ", ", m.name, num(m.value),
                             metrics::higherIsBetter(m.name) ? "<" : ">", num(m.threshold));
    return s;
}

nlohmann::json toJson(const Report& r) {
    nlohmann::json cases = nlohmann::json::array();
    for (const CaseResult& c : r.cases)
        cases.push_back(c.toJson());
    return {{"suite", r.suiteName},
            {"suite_file", r.suiteFile},
            {"shard", r.shard},
            {"suite_sha256", r.suiteSha256},
            {"veil_version", r.veilVersion},
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
                     escape(r.suiteName), r.cases.size(), r.failed(), r.seconds);
    x << fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" time=\"{:.3f}\">\n",
                     escape(r.suiteName), r.cases.size(), r.failed(), r.seconds);
    for (const CaseResult& c : r.cases) {
        x << fmt::format("    <testcase classname=\"veil.regress\" name=\"{}\" time=\"{:.3f}\"",
                         escape(c.name), c.seconds);
        std::string metricsText;
        for (const MetricResult& m : c.metrics)
            metricsText += fmt::format("{} {} (tolerance {}){}\n", m.name, num(m.value),
                                       num(m.threshold), m.passed ? "" : " FAILED");
        if (c.passed) {
            x << ">\n      <system-out>" << escape(metricsText) << "</system-out>\n";
        } else {
            x << ">\n      <failure message=\"" << escape(failureText(c)) << "\">"
              << escape(metricsText) << "</failure>\n";
        }
        x << "    </testcase>\n";
    }
    x << "  </testsuite>\n</testsuites>\n";
    return x.str();
}

std::string html(const Report& r) {
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << escape(r.suiteName)
      << ": veil regress</title>\n<style>\n"
         "body{font-family:sans-serif;margin:1.5em;background:#fafafa}\n"
         "table.m{border-collapse:collapse;margin:.4em 0}\n"
         "table.m td,table.m th{border:1px solid #ccc;padding:2px 8px;text-align:right}\n"
         ".case{border:1px solid #ddd;background:#fff;padding:.6em 1em;margin:1em 0}\n"
         ".fail{border-left:6px solid #c22}.pass{border-left:6px solid #2a2}\n"
         ".bad{color:#c22;font-weight:bold}.ok{color:#272}\n"
         "figure{display:inline-block;margin:0 .6em 0 0}figcaption{font-size:80%;color:#555}\n"
         "img{image-rendering:pixelated;min-width:192px;border:1px solid #999}\n"
         "</style></head><body>\n";
    h << "<h1>" << escape(r.suiteName) << "</h1>\n<p>Suite <code>" << escape(r.suiteFile)
      << "</code>" << (r.shard.empty() ? "" : ", shard " + escape(r.shard)) << ": "
      << r.cases.size() - r.failed() << " of " << r.cases.size() << " cases passed"
      << fmt::format(" ({:.1f} s).</p>\n", r.seconds);
    if (r.failed()) {
        h << "<h2 class=\"bad\">Failed cases</h2>\n<ul>\n";
        for (const CaseResult& c : r.cases)
            if (!c.passed)
                h << "<li><a href=\"#" << escape(c.name) << "\">" << escape(c.name)
                  << "</a>: " << escape(failureText(c)) << "</li>\n";
        h << "</ul>\n";
    }
    for (const CaseResult& c : r.cases) {
        h << "<div class=\"case " << (c.passed ? "pass" : "fail") << "\" id=\"" << escape(c.name)
          << "\">\n<h3>" << escape(c.name) << " <span class=\"" << (c.passed ? "ok" : "bad")
          << "\">" << (c.passed ? "PASS" : "FAIL") << "</span></h3>\n";
        h << "<p>" << escape(c.technique) << " vs " << escape(c.reference) << ", " << c.width << "x"
          << c.height << (c.seeds > 1 ? fmt::format(", mean of {} seeds", c.seeds) : "")
          << ", scene <code>" << escape(c.scene) << "</code>"
          << fmt::format(" ({:.2f} s)", c.seconds) << "</p>\n";
        if (!c.note.empty()) h << "<p><small>" << escape(c.note) << "</small></p>\n";
        if (!c.error.empty()) h << "<p class=\"bad\">" << escape(c.error) << "</p>\n";
        if (!c.metrics.empty()) {
            h << "<table class=\"m\"><tr><th>metric</th><th>value</th><th>tolerance</th><th></th>"
                 "</tr>\n";
            for (const MetricResult& m : c.metrics)
                h << "<tr><td>" << escape(m.name) << "</td><td>" << num(m.value) << "</td><td>"
                  << (metrics::higherIsBetter(m.name) ? "&ge; " : "&le; ") << num(m.threshold)
                  << "</td><td class=\"" << (m.passed ? "ok\">ok" : "bad\">FAIL") << "</td></tr>\n";
            h << "</table>\n";
        }
        const std::pair<const std::string*, std::string> images[] = {
            {&c.renderPng, "render"},
            {&c.referencePng, "reference"},
            {&c.diffPng, fmt::format("max |render - reference| (white = {})", num(c.heatScale))}};
        for (const auto& [path, caption] : images)
            if (!path->empty())
                h << "<figure><img src=\"" << escape(*path) << "\" alt=\"" << escape(caption)
                  << "\"><figcaption>" << escape(caption) << "</figcaption></figure>\n";
        h << "</div>\n";
    }
    h << "</body></html>\n";
    return h.str();
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
    writeTextFileAtomically(dir / "index.html", html(r));
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
