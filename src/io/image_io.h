// Images through OpenImageIO. Writes go to a temporary file that is renamed into place.
#pragma once

#include "base/image.h"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace veil::io {

// Writes by extension: .png (8-bit; the pixels are already display-encoded values in [0,1],
// e.g. the tone-mapped sRGB output) or .exr (half float, linear). 1, 3 or 4 channels are
// written as given; use dropAlpha to write RGB from RGBA.
// Every file carries io::provenanceAttributes() (Software, veil:version, veil:commit) and
// `attributes` (name, string value) in its header (EXR attributes, PNG text chunks). A failure
// is one veil::Error naming the file (describeWriteFailure).
void writeImage(const std::filesystem::path& path, const ImageF& image, bool dropAlpha = true,
                const std::vector<std::pair<std::string, std::string>>& attributes = {});

// The message of a failed image write: "cannot write '<path>': " and, when `savedErrno` is
// ENOSPC or EDQUOT or the file system holding the folder has no space left, "no space left on
// device (the file system holding '<folder>' is full; <library error>)", else the library's
// error (or "the image writer failed").
std::string describeWriteFailure(const std::filesystem::path& path, const std::string& libraryError,
                                 int savedErrno);

// Reads any format OpenImageIO knows into float; 8-bit files come back in [0,1]. A folder,
// device, FIFO or socket is refused before it is opened (a veil::Error naming it).
ImageF readImage(const std::filesystem::path& path);

// The string attributes of an image's header (EXR attributes, PNG text chunks), by name.
std::vector<std::pair<std::string, std::string>>
readImageAttributes(const std::filesystem::path& path);

// Throws veil::Error "cannot read <what> '<path>': ..." when `path` exists and is not a regular
// file (or a link to one): the check every image reader makes before opening.
void checkReadableFile(const std::filesystem::path& path, const char* what);

} // namespace veil::io
