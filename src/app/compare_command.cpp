// `veil compare a.exr b.exr`: image metrics of a against the reference b (src/io/metrics.h),
// a difference heat map, and an exit status from thresholds, as OpenImageIO's idiff does:
// 0 when every --fail threshold holds (warnings only print), 1 when one does not or a file
// cannot be read or compared.
#include "app/cli_checks.h"
#include "app/commands.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "io/image_io.h"
#include "io/metrics.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

struct CompareArgs {
    std::string image, reference, diff;
    std::vector<std::string> metrics, fail, warn;
    double exposure = 1.0;
    std::string tonemap = "clamp";
    double diffScale = 0.0;
};

// "T" (for the first metric) or "METRIC=T", as given to --fail / --warn. A bad item is a usage
// error (exit 2) naming the option and what it accepts.
std::map<std::string, double> parseThresholds(const std::vector<std::string>& items,
                                              const std::string& firstMetric, const char* option) {
    std::map<std::string, double> out;
    for (const std::string& item : items) {
        const auto eq = item.find('=');
        const std::string name = eq == std::string::npos ? firstMetric : item.substr(0, eq);
        const std::string text = eq == std::string::npos ? item : item.substr(eq + 1);
        const auto bad = [&](const std::string& problem) {
            usageError(fmt::format("{} '{}': {}; expected T or METRIC=T with T a finite number "
                                   "(>= 0 but for psnr and ssim) and METRIC one of {}",
                                   option, printable(item, 200), problem,
                                   fmt::join(metrics::metricNames(), ", ")));
        };
        if (!metrics::isMetricName(name))
            bad(fmt::format("unknown metric '{}'", printable(name, 100)));
        const std::optional<double> v = parseFiniteNumber(text);
        if (!v) bad(fmt::format("'{}' is not a finite number", printable(text, 100)));
        if (!metrics::higherIsBetter(name) && *v < 0.0)
            bad(fmt::format("a threshold of {} must be >= 0", name));
        out[name] = *v;
    }
    return out;
}

ImageF readRgb(const std::string& path, const char* what) {
    VEIL_CHECK(fs::exists(path), "{} '{}' does not exist", what, printable(path, 500));
    ImageF img = io::readImage(path);
    VEIL_CHECK(img.channels >= 3, "{} '{}' has {} channel(s): RGB or RGBA needed", what,
               printable(path, 500), img.channels);
    return img;
}

std::string formatValue(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return fmt::format("{:.6g}", v);
}

// Where |a - b| is largest over the RGB channels (the first NaN difference wins, as it is the
// worst): what idiff calls the worst pixel.
struct LargestError {
    double value = 0.0;
    int x = 0, y = 0, channel = 0;
};

LargestError largestError(const ImageF& a, const ImageF& b) {
    LargestError e;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const double d = std::abs(double(a.at(x, y, c)) - double(b.at(x, y, c)));
                if (std::isnan(d)) return {d, x, y, c};
                if (d > e.value) e = {d, x, y, c};
            }
    return e;
}

void runCompare(const CompareArgs& args) {
    std::vector<std::string> names = args.metrics;
    if (names.empty()) names = {"rmse", "maxabs", "relmse", "p99", "psnr", "ssim"};
    for (const std::string& n : names)
        if (!metrics::isMetricName(n))
            usageError(fmt::format("--metric: unknown metric '{}' (known: {})", printable(n, 100),
                                   fmt::join(metrics::metricNames(), ", ")));
    const auto fail = parseThresholds(args.fail, names.front(), "--fail");
    const auto warn = parseThresholds(args.warn, names.front(), "--warn");
    for (const auto* thresholds : {&fail, &warn})
        for (const auto& [n, t] : *thresholds)
            if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    if (args.tonemap != "clamp" && args.tonemap != "aces")
        usageError(fmt::format("--tonemap '{}': use clamp or aces", printable(args.tonemap, 100)));
    if (!args.diff.empty()) {
        if (lowerExtension(args.diff) != ".png" && lowerExtension(args.diff) != ".exr")
            usageError(
                fmt::format("--diff '{}' must end in .png or .exr", printable(args.diff, 500)));
        checkOutputPath(args.diff, "difference image", {args.image, args.reference});
    }
    const ImageF a = readRgb(args.image, "image");
    const ImageF b = readRgb(args.reference, "reference");
    VEIL_CHECK(a.width == b.width && a.height == b.height,
               "image '{}' is {}x{} but reference '{}' is {}x{}: cannot compare",
               printable(args.image, 500), a.width, a.height, printable(args.reference, 500),
               b.width, b.height);
    const metrics::ToneMap op =
        args.tonemap == "aces" ? metrics::ToneMap::Aces : metrics::ToneMap::Clamp;

    std::cout << fmt::format("{} vs {} ({}x{}, linear RGB; ssim on {} tone-mapped sRGB, "
                             "exposure {:g})\n",
                             args.image, args.reference, a.width, a.height, args.tonemap,
                             args.exposure);
    std::vector<std::string> failures, warnings;
    for (const std::string& n : names) {
        const double v = metrics::compute(n, a, b, args.exposure, op);
        std::string note;
        if (auto it = fail.find(n); it != fail.end()) {
            if (!metrics::withinThreshold(n, v, it->second)) {
                failures.push_back(fmt::format("{} {} {} {}", n, formatValue(v),
                                               metrics::higherIsBetter(n) ? "<" : ">",
                                               formatValue(it->second)));
                note = "  FAIL (--fail " + formatValue(it->second) + ")";
            } else
                note = "  ok (--fail " + formatValue(it->second) + ")";
        }
        if (auto it = warn.find(n); it != warn.end() && note.find("FAIL") == std::string::npos &&
                                    !metrics::withinThreshold(n, v, it->second)) {
            warnings.push_back(fmt::format("{} {}", n, formatValue(v)));
            note += "  WARNING (--warn " + formatValue(it->second) + ")";
        }
        std::cout << fmt::format("  {:<7} {}{}\n", n, formatValue(v), note);
    }
    if (const LargestError e = largestError(a, b); e.value != 0.0)
        std::cout << fmt::format("  largest |a - b| {} at x {}, y {} (row 0 at the top), channel "
                                 "{} (image {}, reference {})\n",
                                 formatValue(e.value), e.x, e.y, "RGB"[e.channel],
                                 formatValue(a.at(e.x, e.y, e.channel)),
                                 formatValue(b.at(e.x, e.y, e.channel)));
    if (!args.diff.empty()) {
        io::writeImage(args.diff, metrics::heatMap(a, b, args.diffScale));
        std::cout << "wrote " << args.diff << " (max |a - b| over RGB; white = "
                  << (args.diffScale > 0 ? formatValue(args.diffScale) : "the largest error")
                  << ")\n";
    }
    if (!failures.empty())
        throw Error(fmt::format("{} vs {}: FAILURE: {}", printable(args.image, 500),
                                printable(args.reference, 500), fmt::join(failures, ", ")));
    std::cout << (warnings.empty()
                      ? "PASS\n"
                      : "WARNING: " + fmt::format("{}", fmt::join(warnings, ", ")) + "\n");
}

} // namespace

void addCompareCommand(CLI::App& app) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* cmd = app.add_subcommand(
        "compare", "Compare an image with a reference (linear HDR metrics, heat map, exit status)");
    cmd->add_option("image", args->image, "Image to test (EXR, or any format OpenImageIO reads)")
        ->required();
    cmd->add_option("reference", args->reference, "Reference image, same size")->required();
    cmd->add_option("--metric", args->metrics,
                    "Metric to print (repeatable): rmse, maxabs, relmse (eps 1e-2), p99 (99th "
                    "percentile of |a-b|), psnr, ssim, nrmse; default all but nrmse");
    cmd->add_option("--fail", args->fail,
                    "Exit 1 when a metric is over T (under T for psnr and ssim): T for the first "
                    "--metric, or METRIC=T (repeatable)");
    cmd->add_option("--warn", args->warn, "Print a warning beyond T, same forms as --fail");
    cmd->add_option("--diff", args->diff,
                    "Write a heat map of max |a - b| over RGB (PNG; black = 0, white = the largest "
                    "error or --diff-scale)");
    cmd->add_option("--diff-scale", args->diffScale, "Error shown as white in --diff")
        ->check(finiteRange(1e-30, 1e30));
    cmd->add_option("--exposure", args->exposure, "Exposure before tone mapping for ssim")
        ->check(finiteRange(1e-30, 1e30));
    cmd->add_option("--tonemap", args->tonemap, "Tone map for ssim: clamp (default) or aces");
    cmd->callback([args] { runCompare(*args); });
}

} // namespace veil::app
