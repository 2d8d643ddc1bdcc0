#include "app/shared_options.h"

#include "app/cli_checks.h"
#include "app/version_info.h"
#include "base/error.h"
#include "scene/animation.h"
#include "scene/timeline.h"

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

namespace fs = std::filesystem;

namespace {

std::optional<scene::FilePattern> sequencePattern(const std::string& input) {
    std::error_code ec;
    if (fs::exists(input, ec)) return std::nullopt; // an existing file is taken literally
    try {
        return scene::parseFilePattern(input);
    } catch (const Error& e) {
        usageError(e.what());
    }
}

} // namespace

void FrameOptions::add(CLI::App& cmd, const std::string& what) {
    cmd.add_option("--frame", frame, "One frame of " + what);
    cmd.add_option("--frames", frames,
                   "Frames FIRST-LAST[:STEP] of " + what +
                       " (outputs need a frame pattern, e.g. "
                       "out.####.vdb)");
}

std::vector<int> FrameOptions::list() const {
    if (frame && !frames.empty()) usageError("give --frames or --frame, not both");
    if (frame) return {*frame};
    if (frames.empty()) return {};
    try {
        return scene::parseFrameRange(frames).frames("--frames");
    } catch (const Error& e) {
        usageError(e.what());
    }
}

fs::path inputForFrame(const std::string& input, std::optional<int> frame, const char* what) {
    const std::optional<scene::FilePattern> pattern = sequencePattern(input);
    if (!pattern) {
        if (frame)
            usageError(fmt::format("--frame/--frames need a file sequence as the {} (a name with "
                                   "a frame pattern such as name.####.vdb), not '{}'",
                                   what, input));
        return input;
    }
    if (!frame)
        usageError(
            fmt::format("{} '{}' is a file sequence: give --frame N or --frames A-B", what, input));
    return pattern->fileFor(*frame);
}

void checkFrameInputs(const std::string& input, const std::vector<int>& frames) {
    const std::optional<scene::FilePattern> pattern = sequencePattern(input);
    if (!pattern) return;
    for (int f : frames) {
        const fs::path file = pattern->fileFor(f);
        std::error_code ec;
        VEIL_CHECK(fs::is_regular_file(file, ec), "{}: frame {} of '{}' is missing", file.string(),
                   f, input);
    }
}

fs::path outputForFrame(const std::string& output, std::optional<int> frame, bool single,
                        const char* what) {
    if (!frame) return output;
    std::optional<scene::FilePattern> pattern;
    try {
        pattern = scene::parseFilePattern(output);
    } catch (const Error& e) {
        usageError(fmt::format("{} {}", what, e.what()));
    }
    if (pattern) return pattern->fileFor(*frame);
    if (!single) {
        const fs::path p(output);
        const std::string stem = p.stem().string(), ext = p.extension().string();
        usageError(fmt::format("{} '{}' has no frame pattern for a range of frames (write it as "
                               "{}.####{}, {}.%04d{}, {}.$F4{} or {}.#{})",
                               what, output, stem, ext, stem, ext, stem, ext, stem, ext));
    }
    return output;
}

} // namespace veil::app
