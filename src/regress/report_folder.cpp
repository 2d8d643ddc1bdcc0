#include "regress/report_folder.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <fstream>
#include <sstream>

namespace veil::regress {

namespace fs = std::filesystem;

namespace {

char g_lockFile[PATH_MAX] = {};

std::string readSmallFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

} // namespace

bool validCaseName(const std::string& name) {
    if (name.empty() || name[0] == '.') return false;
    for (char ch : name)
        if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.'))
            return false;
    return true;
}

void checkCaseName(const std::string& name, const std::string& where) {
    VEIL_CHECK(validCaseName(name),
               "{}: case name '{}': use letters, digits, '-', '_' and '.', not starting with "
               "'.' (it names files of the report)",
               where, printable(name, 100));
}

fs::path safePathInside(const fs::path& folder, const std::string& relative,
                        const std::string& what) {
    const fs::path rel(relative);
    VEIL_CHECK(!relative.empty() && rel.is_relative() && !rel.has_root_name(),
               "{} '{}' is not a path relative to '{}'", what, printable(relative, 200),
               folder.string());
    for (const fs::path& part : rel)
        VEIL_CHECK(part != ".." && part != ".", "{} '{}' leaves the folder '{}'", what,
                   printable(relative, 200), folder.string());
    const fs::path full = folder / rel;
    // Symbolic links inside the folder may point out of it: compare resolved paths.
    std::error_code ec;
    const fs::path base = fs::weakly_canonical(folder, ec);
    const fs::path real = ec ? fs::path() : fs::weakly_canonical(full, ec);
    VEIL_CHECK(!ec, "{} '{}': cannot resolve '{}': {}", what, printable(relative, 200),
               full.string(), ec.message());
    const auto [b, r] = std::mismatch(base.begin(), base.end(), real.begin(), real.end());
    VEIL_CHECK(b == base.end() && r != real.end(),
               "{} '{}' resolves to '{}', outside the folder '{}'", what, printable(relative, 200),
               real.string(), base.string());
    return full;
}

ReportLock::ReportLock(const fs::path& dir) : file_(dir / ".veil-regress.lock") {
    const std::string path = fs::absolute(file_).string();
    VEIL_CHECK(path.size() < PATH_MAX, "report folder path too long: '{}'", dir.string());
    // An fcntl lock on the file: released by the kernel when the process ends in any way
    // (SIGKILL, a node's time limit), so a killed run never leaves a stale lock, and it holds
    // across the nodes of a shared file system that supports POSIX locks (NFSv4, Lustre).
    for (int attempt = 0; attempt < 5; ++attempt) {
        // Never through a symbolic link, and only a regular file of its own (not a hard link
        // to a file elsewhere, a FIFO or a device): the pid written below would land there.
        const int fd =
            ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
        VEIL_CHECK(fd >= 0 || errno != ELOOP,
                   "lock file '{}' is a symbolic link: refusing to write through it (remove it "
                   "if no veil regress uses the folder)",
                   file_.string());
        VEIL_CHECK(fd >= 0, "cannot create the lock file '{}': {}", file_.string(),
                   std::strerror(errno));
        struct stat own {};
        if (::fstat(fd, &own) != 0 || !S_ISREG(own.st_mode) || own.st_nlink != 1) {
            ::close(fd);
            throw Error(fmt::format("lock file '{}' is not a regular file of its own (a hard "
                                    "link, folder, FIFO or device): refusing to write it (remove "
                                    "it if no veil regress uses the folder)",
                                    file_.string()));
        }
        struct flock lk {};
        lk.l_type = F_WRLCK;
        lk.l_whence = SEEK_SET;
        if (::fcntl(fd, F_SETLK, &lk) != 0) {
            char buf[128] = {};
            const ssize_t got = ::pread(fd, buf, sizeof buf - 1, 0);
            const std::string text(buf, got > 0 ? static_cast<std::size_t>(got) : 0);
            ::close(fd);
            throw Error(fmt::format("report folder '{}' is in use by another veil regress ({}, "
                                    "lock file '{}'): wait for it to end or choose another -o",
                                    dir.string(),
                                    text.empty()
                                        ? std::string("starting")
                                        : "pid " + printable(text.substr(0, text.find('\n')), 80),
                                    file_.string()));
        }
        // The file may have been removed by the run that held it just before we locked it:
        // then lock the new one.
        struct stat held {
        }, now{};
        if (::fstat(fd, &held) != 0 || ::lstat(file_.c_str(), &now) != 0 ||
            held.st_ino != now.st_ino || held.st_dev != now.st_dev) {
            ::close(fd);
            continue;
        }
        char host[256] = {};
        ::gethostname(host, sizeof host - 1);
        const std::string pid = fmt::format("{} on {}\n", ::getpid(), host);
        const bool ok = ::ftruncate(fd, 0) == 0 &&
                        ::pwrite(fd, pid.data(), pid.size(), 0) == static_cast<ssize_t>(pid.size());
        if (!ok) {
            ::close(fd);
            throw Error(fmt::format("cannot write the lock file '{}'", file_.string()));
        }
        fd_ = fd;
        std::memcpy(g_lockFile, path.c_str(), path.size() + 1);
        return;
    }
    throw Error(fmt::format("cannot take the lock file '{}'", file_.string()));
}

ReportLock::~ReportLock() {
    g_lockFile[0] = '\0';
    std::error_code ec;
    fs::remove(file_, ec);
    ::close(fd_);
}

const char* lockFileForSignals() { return g_lockFile; }

fs::path reportSubfolder(const fs::path& dir, const std::string& name) {
    const fs::path sub = dir / name;
    struct stat st {};
    if (::lstat(sub.c_str(), &st) == 0) {
        VEIL_CHECK(!S_ISLNK(st.st_mode),
                   "'{}' is a symbolic link: refusing to write the report through it (remove it)",
                   sub.string());
        VEIL_CHECK(S_ISDIR(st.st_mode), "'{}' exists and is not a folder (remove it)",
                   sub.string());
        return sub;
    }
    fs::create_directories(dir); // the report folder itself (-o) may be new
    VEIL_CHECK(::mkdir(sub.c_str(), 0777) == 0 || errno == EEXIST, "cannot create '{}': {}",
               sub.string(), std::strerror(errno));
    VEIL_CHECK(::lstat(sub.c_str(), &st) == 0 && S_ISDIR(st.st_mode),
               "'{}' is not a folder after creating it", sub.string());
    return sub;
}

void clearReport(const fs::path& dir) {
    std::error_code ec;
    fs::remove(dir / "results.json", ec);
    for (const char* f : {"results.xml", "index.html"})
        fs::remove(dir / f, ec);
    for (const char* d : {"cases", "images"})
        fs::remove_all(dir / d, ec);
}

void writeCaseFile(const fs::path& dir, const CaseResult& c, const std::string& suiteSha256,
                   const std::string& version) {
    nlohmann::json j = c.toJson();
    j["suite_sha256"] = suiteSha256;
    j["veil_version"] = version;
    writeTextFileAtomically(reportSubfolder(dir, "cases") / (c.name + ".json"),
                            j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

std::optional<CaseResult> readCaseFile(const fs::path& dir, const std::string& name,
                                       const std::string& suiteSha256, const std::string& version) {
    const fs::path file = dir / "cases" / (name + ".json");
    if (!fs::is_regular_file(file)) return std::nullopt;
    try {
        const nlohmann::json j = nlohmann::json::parse(readSmallFile(file));
        if (j.value("suite_sha256", "") != suiteSha256 || j.value("veil_version", "") != version)
            return std::nullopt;
        CaseResult c = CaseResult::fromJson(j);
        if (c.name != name) return std::nullopt;
        for (const std::string* png : {&c.renderPng, &c.referencePng, &c.diffPng})
            if (!png->empty() && !fs::is_regular_file(safePathInside(dir, *png, file.string())))
                return std::nullopt;
        return c;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

void markRunning(const fs::path& dir, const std::string& name) {
    writeTextFileAtomically(reportSubfolder(dir, "cases") / ".running", name + "\n");
}

std::string runningCase(const fs::path& dir) {
    std::string s = readSmallFile(dir / "cases" / ".running");
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r'))
        s.pop_back();
    return s;
}

void clearRunning(const fs::path& dir) {
    std::error_code ec;
    fs::remove(dir / "cases" / ".running", ec);
}

} // namespace veil::regress
