// Text that came from the user (scene files, --set overrides, file names) checked and made
// safe to print in a one-line error message.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace veil {

// Offset of the first byte that does not start or continue a well-formed UTF-8 sequence
// (RFC 3629: no overlongs, no surrogates, nothing above U+10FFFF); nullopt if all is valid.
std::optional<std::size_t> firstInvalidUtf8(std::string_view text);

// `text` for a message: control characters and invalid UTF-8 bytes written as \xHH, cut
// to at most maxChars bytes with "..." appended when longer.
std::string printable(std::string_view text, std::size_t maxChars = 80);

// The extension of `path` ("." included) in lower case, so "x.VDB" reads as ".vdb".
std::string lowerExtension(std::string_view path);

} // namespace veil
