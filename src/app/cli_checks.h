// Option checks for the veil subcommands that CLI11 does not have.
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <string>

namespace veil::app {

// [lo, hi] for a floating-point option. CLI::Range lets NaN through (every comparison with
// NaN is false), so `--smooth nan` was accepted and silently meant no smoothing.
inline CLI::Validator finiteRange(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            double v = 0.0;
            if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
            if (!std::isfinite(v) || v < lo || v > hi)
                return fmt::format("value {} not in range [{:g}, {:g}]", text, lo, hi);
            return {};
        },
        fmt::format("FLOAT in [{:g}, {:g}]", lo, hi));
}

} // namespace veil::app
