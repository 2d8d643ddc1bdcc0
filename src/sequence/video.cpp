// Frame ranges as video (video.h).
#include "sequence/video.h"

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
    const fs::path tmp =
        output.parent_path() / fmt::format(".{}.tmp.mp4", output.filename().string());
    const std::vector<std::string> argv{
        ffmpeg.string(), "-y",      "-loglevel", "error",          "-framerate", rate,
        "-start_number", start,     "-i",        pattern.string(), "-c:v",       "libx264",
        "-pix_fmt",      "yuv420p", tmp.string()};
    const process::ChildExit e = process::runProgram(argv, "ffmpeg");
    if (e.signal || e.status != 0) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw Error(fmt::format("ffmpeg failed encoding '{}' (exit status {})", output.string(),
                                e.signal ? -1 : e.status));
    }
    fs::rename(tmp, output);
}

} // namespace veil::sequence
