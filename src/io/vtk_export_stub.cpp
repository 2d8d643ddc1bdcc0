// The .vti writer and reader of a build without VTK (VEIL_HAVE_VTK off, src/CMakeLists.txt):
// Debian's libvtk9-dev depends on a JDK, so scripts/install-deps.sh installs it only with
// --test. Every other output of veil works without it.
#include "io/vtk_export.h"

#include "base/error.h"

namespace veil::io {

bool vtiSupported() { return false; }

void requireVti(const std::filesystem::path& path) {
    throw Error(fmt::format("'{}': this veil was built without VTK, so it cannot write or read "
                            ".vti files; install VTK (scripts/install-deps.sh --test, or sudo apt "
                            "install libvtk9-dev) and rebuild veil",
                            path.string()));
}

void writeVti(const std::filesystem::path& path, const DenseGrid&) { requireVti(path); }

DenseGrid readVti(const std::filesystem::path& path) {
    requireVti(path);
    return {};
}

} // namespace veil::io
