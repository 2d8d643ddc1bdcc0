// Option checks for the veil subcommands that CLI11 does not have, and the one number parser
// every floating-point option goes through.
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

namespace veil::app {

// The whole of `text` as a finite double: no empty text, no leading or trailing junk, no
// "nan", "inf" or values that overflow (1e400). nullopt otherwise.
inline std::optional<double> parseFiniteNumber(const std::string& text) {
    if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return {};
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v)) return {};
    return v;
}

// A command-line problem found after CLI11's own checks: main() reports it as a usage error
// (exit status 2) like CLI11's, with the command's --help hint.
[[noreturn]] inline void usageError(const std::string& message) {
    throw CLI::ValidationError(message);
}

// [lo, hi] for a floating-point option. CLI::Range lets NaN through (every comparison with
// NaN is false), so `--smooth nan` was accepted and silently meant no smoothing.
inline CLI::Validator finiteRange(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            const std::optional<double> v = parseFiniteNumber(text);
            if (!v) return "'" + text + "' is not a finite number";
            if (*v < lo || *v > hi)
                return fmt::format("value {} not in range [{:g}, {:g}]", text, lo, hi);
            return {};
        },
        fmt::format("FLOAT in [{:g}, {:g}]", lo, hi));
}

} // namespace veil::app
