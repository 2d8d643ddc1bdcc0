#include "regress/report_html.h"

#include "io/metrics.h"
#include "regress/report_assets.h" // generated: assets/report.css, assets/report.js

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace veil::regress {

namespace {

// The metric names of all cases, in the order they first appear.
std::vector<std::string> metricColumns(const Report& r) {
    std::vector<std::string> names;
    for (const CaseResult& c : r.cases)
        for (const MetricResult& m : c.metrics)
            if (std::find(names.begin(), names.end(), m.name) == names.end())
                names.push_back(m.name);
    return names;
}

std::string dataValue(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : ""; }

void summaryTable(std::ostringstream& h, const Report& r) {
    const std::vector<std::string> columns = metricColumns(r);
    h << "<p><label><input type=\"checkbox\" id=\"failed-only\"> failed cases only</label> "
         "<small>(a row opens its case below; a column header sorts)</small></p>\n"
         "<table class=\"summary\" id=\"summary\">\n<thead><tr><th>case</th><th>technique vs "
         "reference</th>";
    for (const std::string& m : columns)
        h << "<th title=\"value (tolerance)\">" << escapeMarkup(m) << "</th>";
    h << "<th>result</th><th>time (s)</th></tr></thead>\n<tbody>\n";
    for (const CaseResult& c : r.cases) {
        const std::string name = escapeMarkup(c.name);
        h << "<tr class=\"" << (c.passed ? "pass-row" : "fail-row") << "\" data-case=\"" << name
          << "\"><td class=\"name\"><a href=\"#" << name << "\">" << name
          << "</a></td><td class=\"what\">" << escapeMarkup(c.technique) << " vs "
          << escapeMarkup(c.reference) << "</td>";
        for (const std::string& col : columns) {
            const auto m = std::find_if(c.metrics.begin(), c.metrics.end(),
                                        [&](const MetricResult& x) { return x.name == col; });
            if (m == c.metrics.end()) {
                h << "<td data-v=\"\"></td>";
                continue;
            }
            h << "<td data-v=\"" << dataValue(m->value) << "\""
              << (m->passed ? "" : " class=\"bad\"") << ">" << reportNumber(m->value) << " <small>("
              << (metrics::higherIsBetter(m->name) ? "&ge;" : "&le;") << " "
              << reportNumber(m->threshold) << ")</small></td>";
        }
        h << "<td class=\"result\">"
          << (c.passed          ? "pass"
              : c.error.empty() ? "FAIL"
                                : "ERROR")
          << "</td><td data-v=\"" << dataValue(c.seconds) << "\">"
          << fmt::format("{:.2f}", c.seconds) << "</td></tr>\n";
    }
    h << "</tbody></table>\n";
}

// The heat map's colour bar: the ramp of io::heatMap as a CSS gradient, with its scale.
void colourBar(std::ostringstream& h, double scale) {
    const auto& stops = metrics::heatMapStops();
    std::string gradient;
    for (std::size_t i = 0; i < stops.size(); ++i) {
        const auto byte = [](float v) { return static_cast<int>(std::lround(v * 255.0f)); };
        gradient += fmt::format("{}rgb({},{},{}) {}%", i ? "," : "", byte(stops[i][0]),
                                byte(stops[i][1]), byte(stops[i][2]), i * 100 / (stops.size() - 1));
    }
    h << "<div class=\"cbar\" data-scale=\"" << dataValue(scale)
      << "\"><div class=\"ramp\" style=\"background:linear-gradient(to right," << gradient
      << ")\"></div>";
    // Ticks at 0, half and the whole scale (five labels crowd a bar 256 px wide).
    for (const double t : {0.0, 0.5, 1.0})
        h << "<span class=\"tick\" style=\"left:" << t * 100.0 << "%\">" << reportNumber(t * scale)
          << "</span>";
    h << "</div>\n";
}

void imageViewer(std::ostringstream& h, const CaseResult& c) {
    if (c.renderPng.empty() && c.referencePng.empty() && c.diffPng.empty()) return;
    // Shown at an integer magnification near 256 px wide (pixels stay square and sharp).
    const int zoom = c.width > 0 ? std::clamp(256 / c.width, 1, 8) : 1;
    const int w = std::max(1, c.width), hgt = std::max(1, c.height);
    const std::string size = fmt::format(" width=\"{}\" height=\"{}\"", w * zoom, hgt * zoom);
    h << "<div class=\"viewer\" data-w=\"" << w << "\" data-h=\"" << hgt
      << "\" data-shown=\"render\">\n";
    const std::string& first = c.renderPng.empty() ? c.referencePng : c.renderPng;
    if (!first.empty()) {
        h << "<figure><img class=\"flip\" src=\"" << escapeMarkup(first) << "\"" << size
          << " alt=\"render\" data-render=\"" << escapeMarkup(c.renderPng) << "\" data-reference=\""
          << escapeMarkup(c.referencePng) << "\"><figcaption>";
        if (!c.referencePng.empty() && !c.renderPng.empty())
            h << "showing <span class=\"shown\">render</span> &middot; <button class=\"flip\" "
                 "title=\"or click the image, or press F\">flip</button> <label><input "
                 "type=\"checkbox\" class=\"blink\"> blink</label>";
        else
            h << "render";
        h << "</figcaption></figure>\n";
    }
    if (!c.diffPng.empty()) {
        h << "<figure style=\"width:" << w * zoom << "px\"><img class=\"heat\" src=\""
          << escapeMarkup(c.diffPng) << "\"" << size << " alt=\"heat map\">\n";
        colourBar(h, c.heatScale);
        h << "<figcaption>max over RGB of |render &minus; reference|, linear radiance; white: "
          << reportNumber(c.heatScale) << " or more (and NaN)</figcaption>\n";
        h << "</figure>\n";
    }
    h << "<div class=\"loupes\">";
    const std::pair<const std::string*, const char*> loupes[] = {
        {&c.renderPng, "render"}, {&c.referencePng, "reference"}, {&c.diffPng, "heat map"}};
    for (const auto& [png, label] : loupes)
        if (!png->empty())
            h << "<div class=\"loupe\" data-src=\"" << escapeMarkup(*png) << "\"><span>" << label
              << "</span></div>";
    h << "<div class=\"where\">move the mouse over an image to magnify it "
         "here</div></div>\n</div>\n";
}

void card(std::ostringstream& h, const CaseResult& c) {
    const std::string name = escapeMarkup(c.name);
    h << "<details class=\"case " << (c.passed ? "pass" : "fail") << "\" id=\"" << name << "\""
      << (c.passed ? "" : " open") << ">\n<summary>" << name << " <span class=\""
      << (c.passed ? "ok\">PASS" : "bad\">FAIL") << "</span><span class=\"sub\">"
      << escapeMarkup(c.technique) << " vs " << escapeMarkup(c.reference)
      << fmt::format(", {:.2f} s", c.seconds) << "</span></summary>\n";
    h << "<p>" << c.width << "x" << c.height
      << (c.seeds > 1 ? fmt::format(", mean of {} seeds", c.seeds) : "") << ", scene <code>"
      << escapeMarkup(c.scene) << "</code></p>\n";
    if (!c.overrides.empty()) {
        h << "<p class=\"overrides\">overrides";
        for (const std::string& o : c.overrides)
            h << " <code>" << escapeMarkup(o) << "</code>";
        h << "</p>\n";
    }
    if (!c.note.empty()) h << "<p><small>" << escapeMarkup(c.note) << "</small></p>\n";
    if (!c.error.empty()) h << "<p class=\"bad\">" << escapeMarkup(c.error) << "</p>\n";
    if (!c.metrics.empty()) {
        h << "<table class=\"m\"><tr><th>metric</th><th>value</th><th>tolerance</th><th></th>"
             "</tr>\n";
        for (const MetricResult& m : c.metrics)
            h << "<tr><td>" << escapeMarkup(m.name) << "</td><td>" << reportNumber(m.value)
              << "</td><td>" << (metrics::higherIsBetter(m.name) ? "&ge; " : "&le; ")
              << reportNumber(m.threshold) << "</td><td class=\""
              << (m.passed ? "ok\">ok" : "bad\">FAIL") << "</td></tr>\n";
        h << "</table>\n";
    }
    imageViewer(h, c);
    h << "</details>\n";
}

} // namespace

std::string escapeMarkup(const std::string& s) {
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

std::string reportNumber(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return fmt::format("{:.5g}", v);
}

std::string failureText(const CaseResult& c) {
    if (!c.error.empty()) return c.error;
    std::string s;
    for (const MetricResult& m : c.metrics)
        if (!m.passed)
            s +=
                fmt::format("{}{} {} {} {}", s.empty() ? "" : ", ", m.name, reportNumber(m.value),
                            metrics::higherIsBetter(m.name) ? "<" : ">", reportNumber(m.threshold));
    return s;
}

std::string reportHtml(const Report& r) {
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << escapeMarkup(r.suiteName)
      << ": veil regress</title>\n<style>\n"
      << assets::kReportCss << "</style></head><body>\n";
    h << "<h1>" << escapeMarkup(r.suiteName) << "</h1>\n<p>Suite <code>"
      << escapeMarkup(r.suiteFile) << "</code>"
      << (r.shard.empty() ? "" : ", shard " + escapeMarkup(r.shard)) << ": <span id=\"totals\">"
      << r.cases.size() - r.failed() << " of " << r.cases.size() << " cases passed</span>"
      << fmt::format(" ({:.1f} s).", r.seconds);
    if (!r.device.empty()) h << " Device: " << escapeMarkup(r.device) << ".";
    if (!r.veilVersion.empty()) h << " veil " << escapeMarkup(r.veilVersion) << ".";
    h << "</p>\n";
    if (r.failed()) {
        h << "<h2 class=\"bad\">Failed cases</h2>\n<ul>\n";
        for (const CaseResult& c : r.cases)
            if (!c.passed)
                h << "<li><a href=\"#" << escapeMarkup(c.name) << "\">" << escapeMarkup(c.name)
                  << "</a>: " << escapeMarkup(failureText(c)) << "</li>\n";
        h << "</ul>\n";
    }
    summaryTable(h, r);
    h << "<h2>Cases</h2>\n<p><small>Failed cases are open; click a passed one to open it. In a "
         "case, click the render to flip to the reference (or press F over it); the boxes "
         "beside magnify render, reference and heat map at the pixel under the "
         "mouse.</small></p>\n";
    for (const CaseResult& c : r.cases)
        card(h, c);
    h << "<script>\n" << assets::kReportJs << "</script>\n</body></html>\n";
    return h.str();
}

} // namespace veil::regress
