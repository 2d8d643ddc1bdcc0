// Images through OpenImageIO. Writes go to a temporary file that is renamed into place.
#pragma once

#include "base/image.h"

#include <filesystem>

namespace veil::io {

// Writes by extension: .png (8-bit; the pixels are already display-encoded values in [0,1],
// e.g. the tone-mapped sRGB output) or .exr (half float, linear). 1, 3 or 4 channels are
// written as given; use dropAlpha to write RGB from RGBA.
void writeImage(const std::filesystem::path& path, const ImageF& image, bool dropAlpha = true);

// Reads any format OpenImageIO knows into float; 8-bit files come back in [0,1].
ImageF readImage(const std::filesystem::path& path);

} // namespace veil::io
