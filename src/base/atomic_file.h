// Outputs are written to a temporary file beside the target and renamed into place, so a
// failure never leaves a truncated file behind (DESIGN.md "Principles").
#pragma once

#include <filesystem>
#include <functional>

namespace veil {

// Calls write(tmpPath) and renames tmpPath to path on success. On any exception the
// temporary is removed and the exception propagates. The temporary keeps the extension of
// `path` so writers that dispatch on the extension (OpenImageIO, VTK) see the right one.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& tmpPath)>& write);

} // namespace veil
