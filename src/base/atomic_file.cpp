#include "base/atomic_file.h"

#include "base/error.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <random>

namespace veil {

namespace fs = std::filesystem;

namespace {

// Temporaries of writes in progress, readable from a signal handler: a slot is claimed
// (Free -> Claimed), filled, then published (Live); the handler only reads Live slots and
// calls unlink(2), which is async-signal-safe.
enum SlotState : int { Free = 0, Claimed = 1, Live = 2 };
struct Slot {
    std::atomic<int> state{Free};
    char path[PATH_MAX] = {};
};
std::array<Slot, 32> g_slots;
static_assert(std::atomic<int>::is_always_lock_free);

Slot* registerTemporary(const fs::path& tmp) {
    const std::string abs = fs::absolute(tmp).string();
    if (abs.size() >= PATH_MAX) return nullptr;
    for (Slot& s : g_slots) {
        int expected = Free;
        if (s.state.compare_exchange_strong(expected, Claimed)) {
            std::memcpy(s.path, abs.c_str(), abs.size() + 1);
            s.state.store(Live);
            return &s;
        }
    }
    return nullptr; // more than 32 writes at once: this one is not cleaned on a signal
}

void unregisterTemporary(Slot* s) {
    if (s) s->state.store(Free);
}

extern "C" void removeTemporariesAndDie(int sig) {
    for (Slot& s : g_slots)
        if (s.state.load() == Live) ::unlink(s.path);
    // SA_RESETHAND restored the default action; the signal is blocked until we return.
    ::raise(sig);
}

// 64-bit FNV-1a: a short, stable tag for a long name.
std::uint64_t fnv1a(std::string_view s) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s)
        h = (h ^ c) * 1099511628211ull;
    return h;
}

[[noreturn]] void failWrite(const fs::path& path, const std::string& problem) {
    throw Error(fmt::format("cannot write '{}': {}", path.string(), problem));
}

// What a writer may have silently got wrong, checked before the rename.
void checkWritten(const fs::path& path, const fs::path& tmp) {
    std::error_code ec;
    const auto size = fs::file_size(tmp, ec);
    if (ec) failWrite(path, "the writer produced no file");
    if (size == 0) failWrite(path, "the writer produced an empty file");
    const int fd = ::open(tmp.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) failWrite(path, std::strerror(errno));
    const bool synced = ::fsync(fd) == 0;
    const int syncErrno = errno;
    ::close(fd);
    if (!synced && syncErrno != EINVAL) failWrite(path, std::strerror(syncErrno));
    // A writer that ignored ENOSPC leaves a short file on a full file system; a successful
    // write that used exactly the last block is refused too, which errs on the safe side.
    struct statvfs st {};
    const fs::path dir = tmp.parent_path().empty() ? fs::path(".") : tmp.parent_path();
    if (::statvfs(dir.c_str(), &st) == 0 && st.f_blocks > 0 &&
        (::geteuid() == 0 ? st.f_bfree : st.f_bavail) == 0)
        failWrite(path, "no space left on device (the file system is full)");
}

// Ten letters or digits from the kernel's random source (std::random_device where getrandom
// fails): about 51 bits, so a name cannot be guessed and planted in advance.
std::string randomTag() {
    static constexpr char kDigits[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    std::uint64_t bits = 0;
    if (::getrandom(&bits, sizeof bits, 0) != static_cast<ssize_t>(sizeof bits)) {
        std::random_device device;
        bits = (std::uint64_t(device()) << 32) ^ device();
    }
    std::string tag(10, 'a');
    for (char& c : tag) {
        c = kDigits[bits % 36];
        bits /= 36;
    }
    return tag;
}

} // namespace

fs::path temporaryPathFor(const fs::path& path) {
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    const std::string stem = path.stem().string(), ext = path.extension().string();
    const std::string tail = fmt::format(".tmp{}-{}", ::getpid(), randomTag());
    constexpr std::size_t kNameMax = 255; // NAME_MAX of Linux file systems
    std::string name = fmt::format(".{}{}{}", stem, tail, ext);
    if (name.size() > kNameMax) {
        const std::string tag = fmt::format("~{:016x}", fnv1a(path.filename().string()));
        const std::size_t fixed = 1 + tag.size() + tail.size() + ext.size();
        name = fixed <= kNameMax
                   ? fmt::format(".{}{}{}{}", stem.substr(0, kNameMax - fixed), tag, tail, ext)
                   : fmt::format(".{}{}", tag, tail); // an absurd extension: drop it
    }
    return dir / name;
}

namespace {

// The temporary of `path`, created empty with O_EXCL | O_NOFOLLOW before any writer opens it:
// a link or file planted at its name is never written through (a new name is drawn when the
// name is taken). Its device and inode go to `made`.
fs::path createTemporary(const fs::path& path, struct stat& made) {
    for (int attempt = 0; attempt < 16; ++attempt) {
        fs::path tmp = temporaryPathFor(path);
        const int fd =
            ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd < 0 && errno == EEXIST) continue;
        if (fd < 0)
            failWrite(path, fmt::format("cannot create a temporary file beside it: {}",
                                        std::strerror(errno)));
        const bool ok = ::fstat(fd, &made) == 0;
        ::close(fd);
        if (!ok) {
            ::unlink(tmp.c_str());
            failWrite(path, "cannot stat its temporary file");
        }
        return tmp;
    }
    failWrite(path, "no free temporary file name beside it after 16 tries");
}

// The temporary is still the file createTemporary() made: a writer replaced by a link (or
// another file) in the meantime is refused rather than renamed into place.
void checkSameTemporary(const fs::path& path, const fs::path& tmp, const struct stat& made) {
    struct stat now {};
    if (::lstat(tmp.c_str(), &now) != 0 || !S_ISREG(now.st_mode) || now.st_nlink != 1 ||
        now.st_dev != made.st_dev || now.st_ino != made.st_ino)
        failWrite(path, fmt::format("its temporary file '{}' was replaced during the write (by a "
                                    "link or another file): refusing to rename it into place",
                                    tmp.string()));
}

} // namespace

void writeFileAtomically(const fs::path& path, const std::function<void(const fs::path&)>& write) {
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    VEIL_CHECK(fs::is_directory(dir), "cannot write '{}': folder '{}' does not exist",
               path.string(), dir.string());
    struct stat made {};
    // Created and registered with SIGINT, SIGTERM and SIGHUP held back, so a signal right
    // after the file appears still finds it registered and removes it.
    sigset_t cleanupSignals, previous;
    sigemptyset(&cleanupSignals);
    for (int sig : {SIGINT, SIGTERM, SIGHUP})
        sigaddset(&cleanupSignals, sig);
    ::pthread_sigmask(SIG_BLOCK, &cleanupSignals, &previous);
    fs::path tmp;
    Slot* slot = nullptr;
    try {
        tmp = createTemporary(path, made);
        slot = registerTemporary(tmp);
    } catch (...) {
        ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
        throw;
    }
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    try {
        write(tmp);
        checkSameTemporary(path, tmp, made);
        checkWritten(path, tmp);
        std::error_code ec;
        fs::rename(tmp, path, ec);
        VEIL_CHECK(!ec, "cannot rename '{}' to '{}': {}", tmp.string(), path.string(),
                   ec.message());
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        unregisterTemporary(slot);
        throw;
    }
    unregisterTemporary(slot);
}

void writeTextFileAtomically(const fs::path& path, std::string_view text) {
    writeFileAtomically(path, [&](const fs::path& tmp) {
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_TRUNC | O_NOFOLLOW | O_CLOEXEC);
        if (fd < 0) failWrite(path, std::strerror(errno));
        std::size_t done = 0;
        while (done < text.size()) {
            const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                const int e = n < 0 ? errno : EIO;
                ::close(fd);
                failWrite(path, std::strerror(e));
            }
            done += static_cast<std::size_t>(n);
        }
        if (::close(fd) != 0) failWrite(path, std::strerror(errno));
    });
}

void checkOutputPath(const fs::path& path, const char* what, const std::vector<fs::path>& inputs) {
    VEIL_CHECK(!path.empty(), "{}: the file name is empty", what);
    VEIL_CHECK(path.has_filename() && path.filename() != "." && path.filename() != "..",
               "{} '{}': not a file name", what, path.string());
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code ec;
    VEIL_CHECK(fs::is_directory(dir, ec), "cannot write {} '{}': folder '{}' does not exist", what,
               path.string(), dir.string());
    VEIL_CHECK(::access(dir.c_str(), W_OK | X_OK) == 0,
               "cannot write {} '{}': folder '{}' is not writable ({})", what, path.string(),
               dir.string(), std::strerror(errno));
    const fs::file_status st = fs::status(path, ec);
    VEIL_CHECK(!fs::is_directory(st), "cannot write {} '{}': it is a folder", what, path.string());
    VEIL_CHECK(!fs::exists(st) || fs::is_regular_file(st),
               "cannot write {} '{}': it exists and is not a regular file", what, path.string());
    VEIL_CHECK(path.filename().string().size() <= 255,
               "cannot write {} '{}': the file name is longer than 255 bytes", what, path.string());
    for (const fs::path& in : inputs)
        VEIL_CHECK(in.empty() || !fs::equivalent(path, in, ec),
                   "{} '{}' would overwrite the input '{}'", what, path.string(), in.string());
}

void installTemporaryFileCleanup() {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler != SIG_DFL) continue;
        struct sigaction sa {};
        sa.sa_handler = removeTemporariesAndDie;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESETHAND;
        ::sigaction(sig, &sa, nullptr);
    }
}

} // namespace veil
