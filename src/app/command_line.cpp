#include "app/command_line.h"

#include "app/version_info.h"

namespace veil::app {

namespace {
std::string& stored() {
    static std::string line;
    return line;
}

std::string quoted(const std::string& arg) {
    const bool plain =
        !arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyz"
                                              "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789-_./=:,+@%") == std::string::npos;
    if (plain) return arg;
    std::string q = "'";
    for (char c : arg)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}
} // namespace

void setCommandLine(int argc, char** argv) {
    std::string line;
    for (int i = 0; i < argc; ++i) {
        if (i) line += ' ';
        line += quoted(argv[i]);
    }
    stored() = line;
}

const std::string& commandLine() { return stored(); }

std::string versionWithCommit() {
    return std::string(VEIL_VERSION) + " (commit " + VEIL_GIT_COMMIT + ")";
}

} // namespace veil::app
