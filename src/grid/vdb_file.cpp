#include "grid/vdb_file.h"

#include "base/error.h"
#include "base/log.h"
#include "grid/vdb_header_check.h"
#include "grid/vdb_reply.h"

#include <openvdb/io/Stream.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

namespace veil::volume {

namespace fs = std::filesystem;

namespace {

using detail::HeaderCheck;

// A trial read taking longer than this is treated as a hang. Decoding runs at well over
// 10 MB/s, so only a file of gigabytes could come near it legitimately.
constexpr int kTrialTimeoutSeconds = 300;

std::string gridNames(const openvdb::io::File& file) {
    std::string names;
    for (auto it = file.beginName(); it != file.endName(); ++it)
        names += fmt::format("{}'{}'", names.empty() ? "" : ", ", boundedText(*it, 60));
    return boundedText(names, 200);
}

// The child never destroys a grid it read, not even one an exception abandons halfway: a tree's
// destructor frees its nodes with tbb::parallel_for, and TBB in a forked child waits for ever
// when the parent's TBB workers were busy at the fork (vdb_reply.h). The child ends with _exit.
void keepUntilExit(const openvdb::GridBase::Ptr& grid) {
    static auto* const kept = new openvdb::GridPtrVec; // never freed, see above
    kept->push_back(grid);
}

// io::Stream's sequential read, one grid at a time, each checked where OpenVDB actually reads
// it: io::Stream reads a grid's descriptor where the previous grid's data ended, not at the
// offset the file gives, so damage inside one grid's data (a flipped mask bit, a compression
// byte) moved the next descriptor read into voxel data and a "type name" of 2 GB was allocated
// and quoted (a fuzz finding, tests/fuzz/regressions/volume/grid-data-shifts-next-descriptor.vdb).
// So before OpenVDB reads a descriptor or a grid header, `check` bounds its strings at that
// position, and a grid must end exactly at the end offset its descriptor gives (where the file
// has offsets).
class CheckedStreamRead : public openvdb::io::Archive {
public:
    openvdb::GridPtrVecPtr read(std::istream& is, HeaderCheck& check, const std::string& file) {
        readHeader(is);
        openvdb::io::StreamMetadata::Ptr meta(new openvdb::io::StreamMetadata);
        openvdb::io::setStreamMetadataPtr(is, meta, /*transfer=*/false);
        openvdb::io::setVersion(is, libraryVersion(), fileVersion());
        openvdb::io::setDataCompression(is, compression());
        openvdb::MetaMap fileMetadata;
        fileMetadata.readMeta(is);
        const std::int32_t count = readGridCount(is);
        auto grids = std::make_shared<openvdb::GridPtrVec>();
        std::vector<openvdb::io::GridDescriptor> descriptors;
        NamedGridMap named;
        for (std::int32_t i = 0; i < count && is; ++i) {
            const std::string where = fmt::format("grid {} of {}", i + 1, count);
            HeaderCheck::Offsets o;
            if (check.known()) o = check.descriptor(std::int64_t(is.tellg()), where);
            openvdb::io::GridDescriptor gd;
            gd.read(is);
            if (!is) break; // truncated: the caller says so
            VEIL_CHECK(openvdb::GridBase::isRegistered(gd.gridType()),
                       "cannot read OpenVDB file '{}' (corrupt?): {} has the unknown grid type "
                       "'{}'",
                       file, where, boundedText(gd.gridType(), 60));
            if (check.known()) check.gridHeader(std::int64_t(is.tellg()), where);
            openvdb::GridBase::Ptr grid = openvdb::GridBase::createGrid(gd.gridType());
            keepUntilExit(grid);
            grid->setSaveFloatAsHalf(gd.saveFloatAsHalf());
            Archive::readGrid(grid, gd, is);
            if (!is) break;
            VEIL_CHECK(!o.usable || std::int64_t(is.tellg()) == o.end,
                       "cannot read OpenVDB file '{}' (corrupt?): {} ('{}') ends at byte {}, but "
                       "its descriptor says {}",
                       file, where, boundedText(gd.gridName(), 60), std::int64_t(is.tellg()),
                       o.end);
            descriptors.push_back(gd);
            grids->push_back(grid);
            named[gd.uniqueName()] = grid;
        }
        for (const openvdb::io::GridDescriptor& gd : descriptors)
            connectInstance(gd, named);
        return grids;
    }
};

// Reads and decodes everything as io::Stream does (CheckedStreamRead) over a stream we hold:
// unlike io::File's eager path it reports the file ending early (the stream fails), which
// io::File reads as zeros. io::File::open reads only the header and grid descriptors, for the grid
// names in errors. Runs in the forked child only (readInChild).
openvdb::GridPtrVecPtr readEagerly(const fs::path& path, std::uint64_t size) {
    std::string names;
    openvdb::GridPtrVecPtr grids;
    bool truncated = false;
    try {
        openvdb::io::File file(path.string());
        file.open(false);
        names = gridNames(file);
        file.close();
        std::ifstream in(path, std::ios::binary);
        VEIL_CHECK(in, "cannot open OpenVDB file '{}'", path.string());
        HeaderCheck check(path, size);
        check.run();
        grids = CheckedStreamRead().read(in, check, path.string());
        truncated = in.fail();
    } catch (const Error&) {
        throw; // ours: names the file already
    } catch (const std::exception& e) {
        throw Error(fmt::format(
            "cannot read OpenVDB file '{}' (truncated or corrupt?){}: {}", path.string(),
            names.empty() ? "" : fmt::format(", grid(s) {}", names), boundedText(e.what())));
    }
    VEIL_CHECK(!truncated && grids, "OpenVDB file '{}' is truncated: it ends inside grid(s) {}",
               path.string(), names.empty() ? "?" : names);
    return grids;
}

bool writeAll(int fd, const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
    std::size_t done = 0;
    while (done < size) {
        // MSG_NOSIGNAL: a reader that died is an error here, not a SIGPIPE ending this process.
        const ssize_t n = ::send(fd, bytes + done, size - done, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += std::size_t(n);
    }
    return true;
}

// Exactly `size` bytes, blocking; false at the end of the stream or on an error.
bool readAll(int fd, void* data, std::size_t size) {
    char* bytes = static_cast<char*>(data);
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::read(fd, bytes + done, size - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += std::size_t(n);
    }
    return true;
}

// A descriptor closed with its owner.
class UniqueFd {
public:
    UniqueFd() = default;
    explicit UniqueFd(int fd) : fd_(fd) {}
    UniqueFd(UniqueFd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
    UniqueFd& operator=(UniqueFd&& o) noexcept {
        if (this != &o) {
            if (fd_ >= 0) ::close(fd_);
            fd_ = std::exchange(o.fd_, -1);
        }
        return *this;
    }
    ~UniqueFd() {
        if (fd_ >= 0) ::close(fd_);
    }
    int get() const { return fd_; }
    explicit operator bool() const { return fd_ >= 0; }

private:
    int fd_ = -1;
};

// What the reader child answered: its grids in shared memory (`memory`, `size` bytes), or an
// error message ('E' and the message in `error`).
struct Reply {
    UniqueFd memory;
    std::uint64_t size = 0;
    std::string error;
};

std::function<void()> gAfterTrialRead;
std::mutex gCrashMutex;
std::string gCrashForTesting;  // a file name whose read crashes the reader (tests)
std::string gDamageForTesting; // a file name whose reply the reader damages (tests)
int gDamageKind = 0;
std::atomic<int> gReaderStarts{0};

// The most of an error reply the child sends and the parent keeps: OpenVDB's messages quote
// what they read (a grid type of 4 GB was quoted whole).
constexpr std::size_t kMaxErrorReply = 4096;

// A reader child never frees the grids it read (keepUntilExit): after replies of this many
// bytes in all (about the memory of those grids) it is replaced by a fresh one.
constexpr std::uint64_t kReaderReplyBudget = std::uint64_t(512) << 20;

struct Request {
    std::uint64_t size = 0;      // the file's size when this process checked its header
    std::uint32_t pathBytes = 0; // then the path
    std::uint32_t crash = 0;     // tests: the reader crashes (SIGSEGV) instead of reading
    std::uint32_t damage = 0;    // tests: writeGridReplyToMemory's `damage`
};

// Sends `n` and, when `fd` >= 0, the descriptor with it (SCM_RIGHTS).
bool sendLength(int socket, std::uint64_t n, int fd) {
    iovec iov{&n, sizeof n};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
    if (fd >= 0) {
        msg.msg_control = control;
        msg.msg_controllen = sizeof control;
        cmsghdr* c = CMSG_FIRSTHDR(&msg);
        c->cmsg_level = SOL_SOCKET;
        c->cmsg_type = SCM_RIGHTS;
        c->cmsg_len = CMSG_LEN(sizeof(int));
        std::memcpy(CMSG_DATA(c), &fd, sizeof fd);
    }
    ssize_t sent;
    do {
        sent = ::sendmsg(socket, &msg, MSG_NOSIGNAL);
    } while (sent < 0 && errno == EINTR);
    return sent == ssize_t(sizeof n); // a unix socket's buffer takes 8 bytes whole
}

// The reader child's loop: a request, the file read and decoded (readEagerly), the reply: the
// grids re-encoded into sealed shared memory (vdb_reply.h writeGridReplyToMemory), its length
// sent with its descriptor; or 'E' and a message, its length first, through the socket. The
// parent closing its end (or dying) ends the child.
[[noreturn]] void serveReads(int fd) {
    for (;;) {
        Request r;
        if (!readAll(fd, &r, sizeof r)) ::_exit(0);
        std::string path(r.pathBytes, '\0');
        if (!readAll(fd, path.data(), path.size())) ::_exit(0);
        if (r.crash) ::raise(SIGSEGV);
        std::string reply;
        try {
            const openvdb::GridPtrVecPtr grids = readEagerly(path, r.size);
            // No TBB here: see vdb_reply.h. The plain values take about 1.5 times the bytes
            // of a blosc-compressed file; the memfd grows past a short guess.
            std::uint64_t n = 0;
            const int memory = writeGridReplyToMemory(*grids, r.size * 2, n, int(r.damage));
            const bool sent = sendLength(fd, n, memory);
            ::close(memory);
            if (!sent) ::_exit(1);
            continue;
        } catch (const std::exception& e) {
            reply = std::string("E") + e.what();
        } catch (...) {
            reply = "Ecannot read OpenVDB file '" + path + "': unknown exception";
        }
        if (reply[0] == 'E' && reply.size() > kMaxErrorReply) reply.resize(kMaxErrorReply);
        const std::uint64_t n = reply.size();
        if (!writeAll(fd, &n, sizeof n) || !writeAll(fd, reply.data(), reply.size())) ::_exit(1);
    }
}

// The trial read in a child process, which also decides what this process gets: the child
// reads the untrusted file and, when it read all of it, writes the grids it holds back
// (vdb_reply.h: COMPRESS_NONE, every value plain, no zip, blosc or mask coding), and this process
// decodes only that re-encoding. Reading the original bytes again here would not be safe: a blosc
// block whose header claims more bytes than its buffer holds overflows the heap without a crash
// (tests/fuzz/regressions/volume/blosc-heap-overflow.vdb: natively the child read it
// "successfully"), and the same overflow would then happen in this process. The re-encoding is
// written by OpenVDB from the tree the child built, so its masks, value counts and sizes agree with
// each other, and it uses no decompressor. The alternative, validating every blosc and zip block's
// header against the node's value count before OpenVDB decodes it, would mean parsing OpenVDB's
// node layout (topology, per-node metadata, half floats) ourselves and would still leave whatever
// other inconsistency the next fuzz run finds. It also closes the window between the child's read
// and ours (a file replaced meanwhile). The cost is one encode in the child and one decode of
// plain values here. Measured on smoke.vdb (2.5 MB, 1.05 M voxels; 2 shared cores at a load of
// about 8, medians of 7 interleaved runs of 40 loads): 57 ms a load before (trial read, then a
// second read of the file here), 70 ms with the re-encoding (+13 ms, 3.7 MB through the pipe,
// written in about 5 ms and decoded here in 2-8 ms instead of the 11 ms of the second read).
// COMPRESS_NONE is the cheapest to write: active-mask coding took 11 ms, blosc 30 ms.
//
// The re-encoding goes through shared memory: the child writes it straight into a memfd mapped
// in its address space, unmaps and seals it (no write, grow or shrink) and passes the descriptor
// over the socket; this process refuses anything but a memfd so sealed of the announced size and
// parses the bytes in place from a read-only mapping. The seal keeps the containment: bytes a
// child whose heap a file damaged could still change while this process parses them would be a
// second way in. Before, the reply was written into an ostringstream, sent through the socket
// in 1 MiB pieces, received into a string, shifted by one byte and parsed from an
// istringstream. Measured on veil-seqgen's 5 M-voxel cloud (17 MB blosc files, 25 MB replies;
// 2 cores, llvmpipe, load 1.3-2.4, medians of 8 reads, four runs alternated): 78 ms a read
// before (decode in the child 31, encode 34, transfer 7-8, shift 1, decode here 4.5), 62 ms
// after (decode 31, encode 23, transfer 0.1, map and decode here 7.9).
//
// One child serves every read of its thread (a frame range's worker reads one file after the
// other) instead of one fork per file, whose cost grows with this process's address space (a GL
// context, the grids of earlier frames). The child is replaced (a fresh fork for the next read)
// after a read that failed or crashed or timed out, so a file that damaged its heap never
// reaches the next file, and after kReaderReplyBudget bytes of replies (it keeps what it read).
class ReaderChild {
public:
    ReaderChild() = default;
    ReaderChild(const ReaderChild&) = delete;
    ReaderChild& operator=(const ReaderChild&) = delete;
    ~ReaderChild() { stop(); }

    // The reply to reading `path` (its grids in shared memory, or an error message), or a
    // veil::Error naming the file when the reader crashed, hung or could not be started.
    Reply read(const fs::path& path, std::uint64_t size, bool crash, int damage) {
        if (owner_ != ::getpid()) forget(); // inherited through a fork of this process
        if (pid_ < 0) start(path);
        Request r;
        r.size = size;
        r.pathBytes = std::uint32_t(path.native().size());
        r.crash = crash ? 1 : 0;
        r.damage = std::uint32_t(damage);
        if (!writeAll(fd_, &r, sizeof r) || !writeAll(fd_, path.c_str(), r.pathBytes)) {
            // It died while idle (killed from outside): one fresh child for this read.
            stop();
            start(path);
            if (!writeAll(fd_, &r, sizeof r) || !writeAll(fd_, path.c_str(), r.pathBytes))
                failed(path);
        }
        const auto deadline =
            std::chrono::steady_clock::now() + std::chrono::seconds(kTrialTimeoutSeconds);
        std::uint64_t n = 0;
        Reply reply;
        if (!receive(&n, sizeof n, deadline, path, &reply.memory)) failed(path);
        if (reply.memory) {
            reply.size = n;
            replied_ += n;
            if (replied_ > kReaderReplyBudget) stop();
            return reply;
        }
        // An error message, bounded by the child.
        try {
            reply.error.resize(std::size_t(n));
        } catch (const std::exception&) {
            stop();
            throw Error(fmt::format("cannot read OpenVDB file '{}': its reader's reply of {} "
                                    "bytes does not fit in memory",
                                    path.string(), n));
        }
        if (!receive(reply.error.data(), reply.error.size(), deadline, path)) failed(path);
        stop();
        return reply;
    }

private:
    void start(const fs::path& path) {
        int sv[2];
        VEIL_CHECK(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) == 0,
                   "cannot read OpenVDB file '{}': no socket for its reader ({})", path.string(),
                   std::strerror(errno));
        // Buffers of 1 MiB: the grids pass in a few writes rather than one context switch per
        // default-sized buffer. Best effort.
        const int buffer = 1 << 20;
        ::setsockopt(sv[0], SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
        ::setsockopt(sv[1], SOL_SOCKET, SO_SNDBUF, &buffer, sizeof buffer);
        pid_t pid = 0;
        {
            const std::lock_guard registries(openVdbIoMutex());
            pid = ::fork();
        }
        if (pid < 0) {
            const int err = errno;
            ::close(sv[0]);
            ::close(sv[1]);
            throw Error(fmt::format("cannot read OpenVDB file '{}': cannot fork its reader ({})",
                                    path.string(), std::strerror(err)));
        }
        if (pid == 0) {
            // Child: no core file for a crash we expect; _exit so that no atexit handler or
            // stdio buffer of the parent runs twice; glibc's heap-corruption report would be a
            // second line before ours. Every other descriptor is closed: a sibling reader
            // holding this process's end of another reader's socket would keep that reader
            // from seeing its parent go.
            const rlimit noCore{0, 0};
            ::setrlimit(RLIMIT_CORE, &noCore);
            const int devNull = ::open("/dev/null", O_WRONLY);
            if (devNull >= 0) ::dup2(devNull, STDERR_FILENO);
            constexpr int kFd = 3;
            if (sv[1] != kFd && ::dup2(sv[1], kFd) < 0) ::_exit(1);
            ::close_range(kFd + 1, ~0U, 0);
            serveReads(kFd);
        }
        ::close(sv[1]);
        pid_ = pid;
        fd_ = sv[0];
        owner_ = ::getpid();
        replied_ = 0;
        ++gReaderStarts;
    }

    // Ends the child: closing the socket ends its loop (SIGKILL first when `kill`), then reaps
    // it. Returns its wait status (0 when none).
    int stop(bool kill = false) {
        if (pid_ < 0) return 0;
        if (kill) ::kill(pid_, SIGKILL);
        ::close(fd_);
        int status = 0;
        pid_t w;
        do {
            w = ::waitpid(pid_, &status, 0);
        } while (w < 0 && errno == EINTR);
        pid_ = -1;
        fd_ = -1;
        return w < 0 ? 0 : status;
    }

    // A forked copy of this process has a copy of the parent's socket: it starts its own.
    void forget() {
        if (fd_ >= 0) ::close(fd_);
        pid_ = -1;
        fd_ = -1;
    }

    // `size` bytes of the reply before `deadline`, and into `memory` a descriptor sent with
    // them (any other is closed); false when the stream ended (the child is gone). A timeout
    // kills the child and throws.
    bool receive(void* data, std::size_t size, std::chrono::steady_clock::time_point deadline,
                 const fs::path& path, UniqueFd* memory = nullptr) {
        char* bytes = static_cast<char*>(data);
        std::size_t done = 0;
        while (done < size) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                                  deadline - std::chrono::steady_clock::now())
                                  .count();
            if (left <= 0) {
                stop(true);
                throw Error(fmt::format("cannot read OpenVDB file '{}': reading it took over "
                                        "{} s (corrupt?)",
                                        path.string(), kTrialTimeoutSeconds));
            }
            pollfd p{fd_, POLLIN, 0};
            const int r = ::poll(&p, 1, int(std::min<long long>(left, 1000)));
            if (r < 0 && errno == EINTR) continue;
            if (r <= 0) continue;
            iovec iov{bytes + done, size - done};
            msghdr msg{};
            msg.msg_iov = &iov;
            msg.msg_iovlen = 1;
            alignas(cmsghdr) char control[CMSG_SPACE(4 * sizeof(int))];
            msg.msg_control = control;
            msg.msg_controllen = sizeof control;
            const ssize_t n = ::recvmsg(fd_, &msg, MSG_CMSG_CLOEXEC);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) return false;
            for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
                if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SCM_RIGHTS) continue;
                const std::size_t count = (c->cmsg_len - CMSG_LEN(0)) / sizeof(int);
                for (std::size_t i = 0; i < count; ++i) {
                    int got = -1;
                    std::memcpy(&got, CMSG_DATA(c) + i * sizeof(int), sizeof got);
                    if (memory && !*memory)
                        *memory = UniqueFd(got);
                    else
                        ::close(got);
                }
            }
            done += std::size_t(n);
        }
        return true;
    }

    // The child ended without a whole reply: a crash (named by its signal) or an exit.
    [[noreturn]] void failed(const fs::path& path) {
        const int status = stop();
        if (WIFSIGNALED(status))
            throw Error(fmt::format("cannot read OpenVDB file '{}' (corrupt?): the OpenVDB "
                                    "reader crashed on it (signal {}, {})",
                                    path.string(), WTERMSIG(status),
                                    ::strsignal(WTERMSIG(status))));
        throw Error(fmt::format("cannot read OpenVDB file '{}' (corrupt?): the trial read ended "
                                "without an answer",
                                path.string()));
    }

    pid_t pid_ = -1, owner_ = -1;
    int fd_ = -1;
    std::uint64_t replied_ = 0;
};

// Every thread that reads has its reader (the prefetch workers read in parallel).
thread_local ReaderChild tReader;

openvdb::GridPtrVecPtr readInChild(const fs::path& path, std::uint64_t size) {
    bool crash = false;
    int damage = 0;
    {
        const std::lock_guard lock(gCrashMutex);
        crash = !gCrashForTesting.empty() && path.filename() == gCrashForTesting;
        if (!gDamageForTesting.empty() && path.filename() == gDamageForTesting)
            damage = gDamageKind;
    }
    const Reply reply = tReader.read(path, size, crash, damage);
    if (gAfterTrialRead) gAfterTrialRead();
    if (reply.memory) {
        try {
            const std::lock_guard registries(openVdbIoMutex());
            return readGridReplyFromMemory(reply.memory.get(), reply.size);
        } catch (const std::exception& e) {
            throw Error(fmt::format("cannot read OpenVDB file '{}': its trial read's "
                                    "re-encoding could not be decoded: {}",
                                    path.string(), boundedText(e.what())));
        }
    }
    if (!reply.error.empty() && reply.error[0] == 'E')
        throw Error(boundedText(reply.error.substr(1), 600));
    throw Error(fmt::format("cannot read OpenVDB file '{}' (corrupt?): the trial read ended "
                            "without an answer",
                            path.string()));
}

} // namespace

int readerStartsForTesting() { return gReaderStarts.load(); }

void setReaderCrashForTesting(const std::string& fileName) {
    const std::lock_guard lock(gCrashMutex);
    gCrashForTesting = fileName;
}

void setReplyDamageForTesting(const std::string& fileName, int kind) {
    const std::lock_guard lock(gCrashMutex);
    gDamageForTesting = fileName;
    gDamageKind = kind;
}

std::mutex& openVdbIoMutex() {
    static std::mutex m;
    return m;
}

void setAfterTrialReadHookForTesting(std::function<void()> hook) {
    gAfterTrialRead = std::move(hook);
}

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

namespace {
thread_local VdbReadScope* tReadScope = nullptr;
}

VdbReadScope::VdbReadScope() : previous_(tReadScope) { tReadScope = this; }
VdbReadScope::~VdbReadScope() { tReadScope = previous_; }

openvdb::GridPtrVecPtr readVdbFile(const fs::path& path) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    std::error_code ec;
    VEIL_CHECK(fs::exists(path, ec), "cannot open volume '{}': no such file", path.string());
    VEIL_CHECK(fs::is_regular_file(path, ec), "cannot open volume '{}': not a regular file",
               path.string());
    std::uint64_t size = 0;
    {
        const auto s = fs::file_size(path, ec);
        VEIL_CHECK(!ec, "cannot open volume '{}': {}", path.string(), ec.message());
        size = s;
    }
    const fs::file_time_type time = fs::last_write_time(path, ec);
    if (tReadScope)
        for (const VdbReadScope::Entry& e : tReadScope->entries_)
            if (e.path == path && e.size == size && e.time == time) return e.grids;
    const auto t0 = std::chrono::steady_clock::now();
    HeaderCheck(path, size).run();
    openvdb::GridPtrVecPtr grids = readInChild(path, size);
    if (tReadScope && !ec) tReadScope->entries_.push_back({path, size, time, grids});
    log::debug(
        "volume '{}': read in a child and decoded here in {:.1f} ms", path.string(),
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    return grids;
}

} // namespace veil::volume
