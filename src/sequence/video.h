// A rendered frame range as a video: numbered PNGs encoded by ffmpeg (H.264, yuv420p so
// players take it), written atomically.
#pragma once

#include <filesystem>
#include <optional>

namespace veil::sequence {

// ffmpeg on $PATH, nullopt when it is not installed.
std::optional<std::filesystem::path> findFfmpeg();

// `ffmpeg -framerate FPS -start_number FIRST -i PATTERN ... OUTPUT` into a temporary beside
// `output`, renamed into place when ffmpeg succeeds; otherwise the temporary is removed and a
// veil::Error names the output and ffmpeg's exit status (-1 when a signal ended it).
void encodeVideo(const std::filesystem::path& ffmpeg, const std::filesystem::path& pattern,
                 int firstFrame, double fps, const std::filesystem::path& output);

} // namespace veil::sequence
