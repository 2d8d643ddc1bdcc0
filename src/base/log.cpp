#include "base/log.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace veil::log {
namespace {
Level initialLevel() {
    // VEIL_LOG=debug|info|warn|error|off overrides the default (warn) for every program.
    const char* env = std::getenv("VEIL_LOG");
    if (!env) return Level::Warn;
    if (!std::strcmp(env, "debug")) return Level::Debug;
    if (!std::strcmp(env, "info")) return Level::Info;
    if (!std::strcmp(env, "error")) return Level::Error;
    if (!std::strcmp(env, "off")) return Level::Off;
    return Level::Warn;
}
std::atomic<Level> g_level{initialLevel()};
} // namespace

void setLevel(Level l) { g_level = l; }
Level level() { return g_level; }

void write(Level l, std::string_view message) {
    static const char* names[] = {"debug", "info", "warning", "error"};
    std::fprintf(stderr, "veil %s: %.*s\n", names[static_cast<int>(l)],
                 static_cast<int>(message.size()), message.data());
}

} // namespace veil::log
