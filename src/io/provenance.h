// What build of Veil made a file: the version, the git commit the build was made from
// (`git describe --always --dirty` at build time, cmake/git_commit.cmake; "unknown" for a source
// tree without .git) and whether tracked files differed from it. `veil --version`, the regress
// and render reports and the header of every image Veil writes (io/image_io.h,
// io/exr_writer.h: Software, veil:version, veil:commit) carry it.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace veil::io {

std::string veilVersion(); // the project version, e.g. "0.1.0"
std::string gitCommit();   // e.g. "46e643f1a2b3", "46e643f1a2b3-dirty" or "unknown"
bool gitTreeDirty();       // tracked files differed from the commit at build time

// "0.1.0 (commit 46e643f1a2b3)", "0.1.0 (commit 46e643f1a2b3-dirty: built with uncommitted
// changes)" or "0.1.0 (commit unknown: built without git history)".
std::string versionLine();

// The image header attributes of the build: Software ("veil 0.1.0"), veil:version,
// veil:commit.
std::vector<std::pair<std::string, std::string>> provenanceAttributes();

} // namespace veil::io
