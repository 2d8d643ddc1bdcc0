// Minimal leveled logger to stderr. GL debug output and loaders route through it.
#pragma once

#include <fmt/format.h>

#include <string_view>

namespace veil::log {

enum class Level { Debug = 0, Info = 1, Warn = 2, Error = 3, Off = 4 };

void setLevel(Level level);
Level level();
void write(Level level, std::string_view message);
// Whether a message of `level` would be written: guard arguments that are costly to make,
// e.g. `if (log::enabled(Level::Debug)) log::debug("{}", describe(x));`.
inline bool enabled(Level l) { return level() <= l; }

template <typename... Args>
void debug(fmt::format_string<Args...> f, Args&&... args) {
    if (level() <= Level::Debug) write(Level::Debug, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void info(fmt::format_string<Args...> f, Args&&... args) {
    if (level() <= Level::Info) write(Level::Info, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void warn(fmt::format_string<Args...> f, Args&&... args) {
    if (level() <= Level::Warn) write(Level::Warn, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void error(fmt::format_string<Args...> f, Args&&... args) {
    if (level() <= Level::Error) write(Level::Error, fmt::format(f, std::forward<Args>(args)...));
}

} // namespace veil::log
