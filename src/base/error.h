// Veil's one error type: what failed and, where useful, what to do about it.
// Every loader, parser and GL helper throws veil::Error; the CLI prints e.what() on one
// line and exits non-zero.
#pragma once

#include <fmt/format.h>
#include <stdexcept>
#include <string>

namespace veil {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// VEIL_CHECK(cond, "fmt {}", args...) throws veil::Error with the formatted message.
#define VEIL_CHECK(cond, ...)                                                                      \
    do {                                                                                           \
        if (!(cond)) throw ::veil::Error(fmt::format(__VA_ARGS__));                                \
    } while (0)

} // namespace veil
