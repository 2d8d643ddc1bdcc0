// Outputs are written to a temporary file beside the target and renamed into place, so a
// failure never leaves a truncated file behind.
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

namespace veil {

// Creates tmpPath (temporaryPathFor) empty, with O_CREAT | O_EXCL | O_NOFOLLOW, so a link
// or file already at that name is never written through; calls write(tmpPath) and renames
// tmpPath to path on success, refusing a tmpPath that is no longer the file it created (a
// link or another file swapped in). On any exception the temporary is removed and the
// exception propagates. The temporary keeps the extension of
// `path` so writers that dispatch on the extension (OpenImageIO, VTK) see the right one.
// Before the rename the result is checked, because some writers (OpenVDB's File::write)
// ignore write errors: the file must exist, be non-empty, survive fsync, and the file
// system must not be full (a writer that hit ENOSPC leaves a short file and a full disk).
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& tmpPath)>& write);

// writeFileAtomically with `text` written by write(2), every result checked.
void writeTextFileAtomically(const std::filesystem::path& path, std::string_view text);

// A temporary name for `path`: ".<stem>.tmp<pid>-<tag><ext>" beside it, <tag> ten random
// letters or digits drawn anew on every call (so the name cannot be planted in advance), the
// stem shortened and hashed when the name would pass NAME_MAX (255 bytes).
std::filesystem::path temporaryPathFor(const std::filesystem::path& path);

// Throws veil::Error naming `path` unless it can be written: its folder exists and is
// writable, it is not a folder or another non-regular file, and it is none of `inputs`.
// Run before long work, so a bad -o fails before rendering rather than after.
void checkOutputPath(const std::filesystem::path& path, const char* what,
                     const std::vector<std::filesystem::path>& inputs = {});

// On SIGINT, SIGTERM and SIGHUP, removes the temporaries of writes in progress and dies of
// the same signal. Signals that are ignored (nohup) stay ignored. For programs' main().
void installTemporaryFileCleanup();

} // namespace veil
