#include "volume/vdb_file.h"

#include "base/error.h"
#include "base/log.h"

#include <openvdb/io/Stream.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <mutex>

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace veil::volume {

namespace fs = std::filesystem;

namespace {

// A trial read taking longer than this is treated as a hang. Decoding runs at well over
// 10 MB/s, so only a file of gigabytes could come near it legitimately.
constexpr int kTrialTimeoutSeconds = 300;

std::string gridNames(const openvdb::io::File& file) {
    std::string names;
    for (auto it = file.beginName(); it != file.endName(); ++it)
        names += fmt::format("{}'{}'", names.empty() ? "" : ", ", boundedText(*it, 60));
    return boundedText(names, 200);
}

// Reads and decodes everything through io::Stream over a stream we hold: unlike io::File's
// eager path it reports the file ending early (the stream fails), which io::File reads as
// zeros. io::File::open reads only the header and grid descriptors, for the grid names in
// errors. Values are walked serially (no TBB: this also runs in the forked child, where the
// parent's TBB worker threads do not exist).
openvdb::GridPtrVecPtr readEagerly(const fs::path& path, bool walk) {
    std::string names;
    openvdb::GridPtrVecPtr grids;
    bool truncated = false;
    try {
        openvdb::io::File file(path.string());
        file.open(false);
        names = gridNames(file);
        file.close();
        std::ifstream in(path, std::ios::binary);
        VEIL_CHECK(in, "cannot open it");
        openvdb::io::Stream stream(in, /*delayLoad=*/false);
        grids = stream.getGrids();
        truncated = in.fail();
        if (walk && !truncated)
            for (const auto& g : *grids)
                if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g)) {
                    volatile float sink = 0.0f;
                    for (auto it = f->tree().cbeginValueOn(); it; ++it)
                        sink = sink + *it;
                    (void)sink;
                }
    } catch (const std::exception& e) {
        throw Error(fmt::format(
            "cannot read OpenVDB file '{}' (truncated or corrupt?){}: {}", path.string(),
            names.empty() ? "" : fmt::format(", grid(s) {}", names), boundedText(e.what())));
    }
    VEIL_CHECK(!truncated && grids, "OpenVDB file '{}' is truncated: it ends inside grid(s) {}",
               path.string(), names.empty() ? "?" : names);
    return grids;
}

void writeAll(int fd, const std::string& s) {
    std::size_t done = 0;
    while (done < s.size()) {
        const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
        if (n <= 0) return;
        done += std::size_t(n);
    }
}

// The trial read in a child process. Returns normally when the child read the whole file.
void trialReadInChild(const fs::path& path) {
    int fds[2];
    if (::pipe(fds) != 0) {
        log::warn("volume '{}': no pipe for the trial read ({}); reading without it", path.string(),
                  std::strerror(errno));
        return;
    }
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        log::warn("volume '{}': cannot fork for the trial read ({}); reading without it",
                  path.string(), std::strerror(errno));
        return;
    }
    if (pid == 0) {
        // Child: no core file for a crash we expect; _exit so that no atexit handler or stdio
        // buffer of the parent runs twice.
        ::close(fds[0]);
        const rlimit noCore{0, 0};
        ::setrlimit(RLIMIT_CORE, &noCore);
        // glibc's heap-corruption report would be a second line before ours.
        const int devNull = ::open("/dev/null", O_WRONLY);
        if (devNull >= 0) ::dup2(devNull, STDERR_FILENO);
        std::string reply = "K";
        try {
            readEagerly(path, true);
        } catch (const std::exception& e) {
            reply = std::string("E") + e.what();
        } catch (...) {
            reply = "Ecannot read OpenVDB file '" + path.string() + "': unknown exception";
        }
        writeAll(fds[1], reply);
        ::_exit(0);
    }
    ::close(fds[1]);
    std::string reply;
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::seconds(kTrialTimeoutSeconds);
    bool timedOut = false;
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                              deadline - std::chrono::steady_clock::now())
                              .count();
        if (left <= 0) {
            timedOut = true;
            break;
        }
        pollfd p{fds[0], POLLIN, 0};
        const int r = ::poll(&p, 1, int(std::min<long long>(left, 1000)));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) continue;
        char buf[4096];
        const ssize_t n = ::read(fds[0], buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break; // end of file: the child is done or dead
        if (reply.size() < 8192) reply.append(buf, std::size_t(n));
    }
    ::close(fds[0]);
    if (timedOut) ::kill(pid, SIGKILL);
    int status = 0;
    pid_t w;
    do {
        w = ::waitpid(pid, &status, 0);
    } while (w < 0 && errno == EINTR);
    if (timedOut)
        throw Error(fmt::format("cannot read OpenVDB file '{}': reading it took over {} s "
                                "(corrupt?)",
                                path.string(), kTrialTimeoutSeconds));
    if (!reply.empty() && reply[0] == 'K') return;
    if (!reply.empty() && reply[0] == 'E') throw Error(boundedText(reply.substr(1), 600));
    if (w == pid && WIFSIGNALED(status))
        throw Error(fmt::format("cannot read OpenVDB file '{}' (corrupt?): the OpenVDB reader "
                                "crashed on it (signal {}, {})",
                                path.string(), WTERMSIG(status), ::strsignal(WTERMSIG(status))));
    throw Error(fmt::format("cannot read OpenVDB file '{}' (corrupt?): the trial read ended "
                            "without an answer",
                            path.string()));
}

} // namespace

std::string boundedText(const std::string& text, std::size_t limit) {
    std::string out;
    out.reserve(std::min(text.size(), limit) + 3);
    for (char c : text) {
        if (out.size() >= limit) {
            out += "...";
            break;
        }
        const auto u = static_cast<unsigned char>(c);
        out.push_back(u < 0x20 || u == 0x7f ? '?' : c);
    }
    return out;
}

openvdb::GridPtrVecPtr readVdbFile(const fs::path& path) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    std::error_code ec;
    VEIL_CHECK(fs::exists(path, ec), "cannot open volume '{}': no such file", path.string());
    VEIL_CHECK(fs::is_regular_file(path, ec), "cannot open volume '{}': not a regular file",
               path.string());
    const auto t0 = std::chrono::steady_clock::now();
    trialReadInChild(path);
    const auto t1 = std::chrono::steady_clock::now();
    openvdb::GridPtrVecPtr grids = readEagerly(path, false);
    const auto t2 = std::chrono::steady_clock::now();
    log::debug("volume '{}': trial read in a child {:.1f} ms, read {:.1f} ms", path.string(),
               std::chrono::duration<double, std::milli>(t1 - t0).count(),
               std::chrono::duration<double, std::milli>(t2 - t1).count());
    return grids;
}

} // namespace veil::volume
