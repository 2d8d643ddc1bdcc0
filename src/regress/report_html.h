// index.html of a `veil regress` report: a summary table first (one row per case: metric values
// against their tolerances, pass/fail, time; each row links to its card), then one card per
// case with the numbers, the render and the reference in one view that flips between them on a
// click (or F), a magnifier that follows the mouse over render, reference and heat map at once
// (wheel: zoom), and the heat map with a colour bar of its scale. One self-contained page (CSS
// and script inline, images beside it); opening `index.html#CASE` opens that case's card. The
// style and script are regress/assets/report.{css,js}, compiled in (src/CMakeLists.txt).
#pragma once

#include "regress/report.h"

#include <string>

namespace veil::regress {

std::string reportHtml(const Report& report);

// Shared with the JUnit writer.
std::string escapeMarkup(const std::string& s); // HTML and XML text and attributes
std::string reportNumber(double v);             // 5 significant digits, nan, inf
std::string failureText(const CaseResult& c);   // "maxabs 0.3 > 0.1, ..." or the error

} // namespace veil::regress
