#include "io/provenance.h"

// Generated at build time (cmake/git_commit.cmake); this is the only unit that includes it.
#include "app/version_info.h"

namespace veil::io {

std::string veilVersion() { return VEIL_VERSION_TEXT; }

std::string gitCommit() { return VEIL_GIT_COMMIT; }

bool gitTreeDirty() { return VEIL_GIT_DIRTY != 0; }

std::string versionLine() {
    const std::string commit = gitCommit();
    std::string note;
    if (commit == "unknown")
        note = ": built without git history";
    else if (gitTreeDirty())
        note = ": built with uncommitted changes";
    return veilVersion() + " (commit " + commit + note + ")";
}

std::vector<std::pair<std::string, std::string>> provenanceAttributes() {
    return {{"Software", "veil " + veilVersion()},
            {"veil:version", veilVersion()},
            {"veil:commit", gitCommit()}};
}

} // namespace veil::io
