// What several commands share: the command line veil was started with (the provenance written
// into outputs) and --frame N / --frames A-B[:S] for the commands that turn an input into files
// (voxelize, export): the frames asked for, the input of a frame of a file sequence and the
// output of a frame (its frame pattern filled in, scene/animation.h).
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace veil::app {

// Records argv (main calls it once, before parsing).
void setCommandLine(int argc, char** argv);
// argv joined by spaces, each argument that needs it in single quotes (shell syntax).
const std::string& commandLine();
// "0.1.0 (commit 3ea8d63abcde)": the version and the commit the build was configured from.
std::string versionWithCommit();

struct FrameOptions {
    std::optional<int> frame;
    std::string frames;

    void add(CLI::App& cmd, const std::string& what);
    bool given() const { return frame.has_value() || !frames.empty(); }
    // The frames asked for, in order (usage errors for both options or a malformed range);
    // empty when neither option is given.
    std::vector<int> list() const;
};

// The file of frame `frame` of `input` when `input` names a sequence (a frame pattern and no
// file of that literal name); `input` itself otherwise. With frames asked for, an input that
// is not a sequence is a usage error, and so is a sequence without frames asked for (`what`
// names the input in messages).
std::filesystem::path inputForFrame(const std::string& input, std::optional<int> frame,
                                    const char* what);

// Every frame's input file exists (one line naming the first missing file and its frame).
void checkFrameInputs(const std::string& input, const std::vector<int>& frames);

// The output of frame `frame` (sequence/range_render.h outputFor): a range needs a frame
// pattern in the output name (usage error otherwise).
std::filesystem::path outputForFrame(const std::string& output, std::optional<int> frame,
                                     bool single, const char* what);

} // namespace veil::app
