#include "base/output_lock.h"

#include "base/error.h"
#include "base/sha256.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <thread>

namespace veil {

namespace fs = std::filesystem;

namespace {

// Frame f is the byte at offset f - INT_MIN + 1 (1 .. 2^32); offset 0 stays unlocked except by
// a whole-file lock (l_len 0: to the end of the file and beyond).
off_t offsetOf(int frame) { return off_t(frame) - off_t(INT_MIN) + 1; }
int frameAt(off_t offset) { return int(offset - 1 + off_t(INT_MIN)); }

struct Span {
    off_t start = 0, length = 0; // length 0: the whole file
};

// Runs of consecutive frames as one span each (a range of 100000 frames is one lock).
std::vector<Span> spansOf(std::vector<int> frames) {
    std::sort(frames.begin(), frames.end());
    frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
    std::vector<Span> spans;
    for (int f : frames) {
        if (!spans.empty() && spans.back().start + spans.back().length == offsetOf(f))
            ++spans.back().length;
        else
            spans.push_back({offsetOf(f), 1});
    }
    if (spans.empty()) spans.push_back({0, 0});
    return spans;
}

bool sameFile(const struct stat& a, const struct stat& b) {
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

// The open file is still the one linked at `file` (a run releasing the lock removes it).
bool stillLinked(int fd, const fs::path& file) {
    struct stat held {
    }, now{};
    return ::fstat(fd, &held) == 0 && ::lstat(file.c_str(), &now) == 0 && sameFile(held, now);
}

} // namespace

fs::path OutputLock::fileFor(const fs::path& output) {
    const fs::path dir = output.has_parent_path() ? output.parent_path() : fs::path(".");
    const std::string name = output.filename().string();
    constexpr std::size_t kNameMax = 255;
    if (name.size() + 6 <= kNameMax) return dir / fmt::format(".{}.lock", name);
    return dir / fmt::format(".{}~{}.lock", name.substr(0, 200), sha256Hex(name).substr(0, 16));
}

OutputLock::OutputLock(const fs::path& output, const std::vector<int>& frames,
                       const std::string& who)
    : file_(fileFor(output)) {
    const std::vector<Span> spans = spansOf(frames);
    // A whole-file lock held by another process for a moment is a run releasing its lock
    // (its destructor); a video run holds one for its whole run: waited for up to 0.5 s.
    for (int attempt = 0; attempt < 25; ++attempt) {
        // Never through a symbolic link, and only a regular file of its own (not a hard link
        // to a file elsewhere, a FIFO or a device).
        const int fd =
            ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
        VEIL_CHECK(fd >= 0 || errno != ELOOP,
                   "lock file '{}' of output '{}' is a symbolic link: refusing to use it (remove "
                   "it if no {} writes the output)",
                   file_.string(), output.string(), who);
        VEIL_CHECK(fd >= 0, "cannot create the lock file '{}' of output '{}': {}", file_.string(),
                   output.string(), std::strerror(errno));
        struct stat own {};
        if (::fstat(fd, &own) != 0 || !S_ISREG(own.st_mode) || own.st_nlink != 1) {
            ::close(fd);
            throw Error(fmt::format("lock file '{}' of output '{}' is not a regular file of its "
                                    "own (a hard link, folder, FIFO or device): refusing to use "
                                    "it (remove it if no {} writes the output)",
                                    file_.string(), output.string(), who));
        }
        struct flock held {};
        bool conflict = false;
        for (const Span& s : spans) {
            struct flock lk {};
            lk.l_type = F_WRLCK;
            lk.l_whence = SEEK_SET;
            lk.l_start = s.start;
            lk.l_len = s.length;
            if (::fcntl(fd, F_SETLK, &lk) == 0) continue;
            const int e = errno;
            if (e != EAGAIN && e != EACCES) {
                ::close(fd);
                throw Error(fmt::format("cannot lock '{}' (the lock file of output '{}'): {}",
                                        file_.string(), output.string(), std::strerror(e)));
            }
            held = lk;
            if (::fcntl(fd, F_GETLK, &held) != 0 || held.l_type == F_UNLCK) held = lk;
            conflict = true;
            break;
        }
        if (!conflict) {
            if (!stillLinked(fd, file_)) { // removed by a run releasing it: lock the new one
                ::close(fd);
                continue;
            }
            fd_ = fd;
            return;
        }
        ::close(fd); // releases the spans this attempt took
        const bool wholeFile = held.l_start == 0 && held.l_len == 0;
        if (wholeFile && attempt + 1 < 25) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            continue;
        }
        const std::string pid =
            held.l_pid > 0 ? fmt::format("pid {}", held.l_pid) : std::string("pid unknown");
        // The first frame of ours that the other run holds.
        std::string what = fmt::format("output '{}'", output.string());
        const off_t heldEnd = held.l_len == 0 ? LLONG_MAX : held.l_start + held.l_len;
        for (const Span& s : spans)
            if (!wholeFile && s.length != 0 && s.start < heldEnd &&
                held.l_start < s.start + s.length) {
                what = fmt::format("frame {} of output '{}'",
                                   frameAt(std::max(s.start, held.l_start)), output.string());
                break;
            }
        throw Error(fmt::format("{} is being written by another {} ({}, lock file '{}'): wait "
                                "for it to end, or render other frames or to another -o",
                                what, who, pid, file_.string()));
    }
    throw Error(fmt::format("cannot take the lock file '{}' of output '{}'", file_.string(),
                            output.string()));
}

OutputLock::~OutputLock() {
    // The whole file when no other process holds a part of it: then nobody needs it and it is
    // removed (a run that opened it meanwhile finds it unlinked and opens the new one).
    struct flock lk {};
    lk.l_type = F_WRLCK;
    lk.l_whence = SEEK_SET;
    if (::fcntl(fd_, F_SETLK, &lk) == 0 && stillLinked(fd_, file_)) ::unlink(file_.c_str());
    ::close(fd_);
}

} // namespace veil
