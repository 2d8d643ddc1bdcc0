// Frame ranges as video (video.h).
#include "sequence/video.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/process.h"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace veil::sequence {

namespace fs = std::filesystem;

std::optional<fs::path> findFfmpeg() { return process::findOnPath("ffmpeg"); }

void encodeVideo(const fs::path& ffmpeg, const fs::path& pattern, int firstFrame, double fps,
                 const fs::path& output) {
    const std::string rate = fmt::format("{}", fps), start = std::to_string(firstFrame);
    // ffmpeg -y overwrites the temporary that writeFileAtomically made (a new random name,
    // created exclusively, so no link planted beside the output is written through).
    writeFileAtomically(output, [&](const fs::path& tmp) {
        const std::vector<std::string> argv{
            ffmpeg.string(), "-y",      "-loglevel", "error",          "-framerate", rate,
            "-start_number", start,     "-i",        pattern.string(), "-c:v",       "libx264",
            "-pix_fmt",      "yuv420p", tmp.string()};
        const process::ChildExit e = process::runProgram(argv, "ffmpeg");
        if (e.signal || e.status != 0)
            throw Error(fmt::format("ffmpeg failed encoding '{}' (exit status {})", output.string(),
                                    e.signal ? -1 : e.status));
    });
}

} // namespace veil::sequence
