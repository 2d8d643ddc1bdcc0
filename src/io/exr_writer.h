// Multi-channel OpenEXR files with metadata, through OpenImageIO, written to a temporary file
// renamed into place (base/atomic_file.h).
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace veil::io {

struct ExrImage {
    int width = 0, height = 0;
    // Channel names in file order, e.g. R, G, B, A, Z, fog.R, ...; OpenEXR sorts them by name
    // on disk, OpenImageIO restores R, G, B, A first when reading.
    std::vector<std::string> channels;
    std::vector<float> pixels; // interleaved, row 0 = top
    // false: 32-bit float channels; true: half, rounded to nearest even on the CPU
    // (base/half.h) before OpenImageIO sees it.
    bool half = false;
    std::vector<std::pair<std::string, std::string>> strings; // header string attributes
    // 4x4 matrices, column-major as GLM stores them: written as OpenEXR m44f in its row-vector
    // convention (OpenEXR's m[i][j] is GLM's m[i][j], i = column).
    std::vector<std::pair<std::string, std::array<float, 16>>> matrices;
};

void writeExr(const std::filesystem::path& path, const ExrImage& image);

} // namespace veil::io
