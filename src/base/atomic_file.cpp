#include "base/atomic_file.h"

#include "base/error.h"

#include <unistd.h>

namespace veil {

void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path&)>& write) {
    namespace fs = std::filesystem;
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    VEIL_CHECK(fs::is_directory(dir), "cannot write '{}': folder '{}' does not exist",
               path.string(), dir.string());
    const fs::path tmp = dir / fmt::format(".{}.tmp{}{}", path.stem().string(), ::getpid(),
                                           path.extension().string());
    try {
        write(tmp);
        std::error_code ec;
        fs::rename(tmp, path, ec);
        VEIL_CHECK(!ec, "cannot rename '{}' to '{}': {}", tmp.string(), path.string(),
                   ec.message());
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw;
    }
}

} // namespace veil
