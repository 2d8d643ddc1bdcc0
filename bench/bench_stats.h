// Small statistics shared by veil-bench's modes: wall-clock milliseconds, medians and a
// pass entry (name, median, min, max) in the JSON every bench writes (bench/README.md).
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

namespace veil::bench {

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// {"name", "median_ms", "min_ms", "max_ms"} of `v` (all 0 when it is empty).
inline nlohmann::json passStats(const std::string& name, const std::vector<double>& v) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return {{"name", name},
            {"median_ms", median(v)},
            {"min_ms", v.empty() ? 0.0 : *lo},
            {"max_ms", v.empty() ? 0.0 : *hi}};
}

} // namespace veil::bench
