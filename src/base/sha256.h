// SHA-256 (FIPS 180-4) of files, for recording which scene an image was rendered from.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace veil {

// Lower-case hex digest (64 characters) of `bytes`.
std::string sha256Hex(std::string_view bytes);

// Digest of a file's content; throws veil::Error naming the file when it cannot be read.
std::string sha256File(const std::filesystem::path& path);

} // namespace veil
