// The command line veil was started with, for the provenance written into outputs.
#pragma once

#include <string>

namespace veil::app {

// Records argv (main calls it once, before parsing).
void setCommandLine(int argc, char** argv);
// argv joined by spaces, each argument that needs it in single quotes (shell syntax).
const std::string& commandLine();
// "0.1.0 (commit 3ea8d63abcde)": the version and the commit the build was configured from.
std::string versionWithCommit();

} // namespace veil::app
