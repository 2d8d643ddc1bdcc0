// Child processes and signals (process.h).
#include "base/process.h"

#include "base/error.h"

#include <fmt/format.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>

extern char** environ;

namespace veil::process {

namespace {

// StopOnSignal.
std::atomic<bool> gStop{false};
std::atomic<int> gStopSignal{0};
struct sigaction gStopOld[2]{};

// The first signal stops the loop after its current step; a second one gets the handler that
// was there before.
extern "C" void onStopSignal(int sig) {
    if (gStop.exchange(true)) {
        const struct sigaction& old = gStopOld[sig == SIGINT ? 0 : 1];
        sigaction(sig, &old, nullptr);
        ::raise(sig);
        return;
    }
    gStopSignal.store(sig);
}

// forwardSignals.
volatile sig_atomic_t gSignal = 0;
std::array<std::atomic<pid_t>, 128> gChildren{};
struct sigaction gPrevious[3] = {};
constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};
void (*gCleanup)() = nullptr;

extern "C" void onForwardedSignal(int sig) {
    gSignal = sig;
    bool children = false;
    for (auto& c : gChildren)
        if (const pid_t p = c.load(); p > 0) {
            ::kill(p, sig);
            children = true;
        }
    if (children) return; // the parent's wait ends, it cleans up and calls dieOfSignal
    if (gCleanup) gCleanup();
    for (int i = 0; i < 3; ++i)
        if (kSignals[i] == sig) {
            struct sigaction dfl {};
            dfl.sa_handler = SIG_DFL;
            ::sigaction(sig, &dfl, nullptr);
            // The previous handler (temporaries of base/atomic_file.h) raises the signal again,
            // which the default action then delivers once this handler returns.
            if (gPrevious[i].sa_handler != SIG_DFL && gPrevious[i].sa_handler != SIG_IGN)
                gPrevious[i].sa_handler(sig);
            else
                ::raise(sig);
        }
}

} // namespace

StopOnSignal::StopOnSignal() {
    gStop = false;
    int i = 0;
    for (int sig : {SIGINT, SIGTERM}) {
        struct sigaction sa {};
        sa.sa_handler = onStopSignal;
        sigemptyset(&sa.sa_mask);
        sigaction(sig, &sa, &gStopOld[i++]);
    }
}

StopOnSignal::~StopOnSignal() {
    sigaction(SIGINT, &gStopOld[0], nullptr);
    sigaction(SIGTERM, &gStopOld[1], nullptr);
}

const std::atomic<bool>& StopOnSignal::stopFlag() { return gStop; }

int StopOnSignal::signal() { return gStopSignal.load(); }

void forwardSignals(void (*cleanup)()) {
    static bool installed = false;
    if (installed) return;
    installed = true;
    gCleanup = cleanup;
    for (int i = 0; i < 3; ++i) {
        struct sigaction old {};
        if (::sigaction(kSignals[i], nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
        gPrevious[i] = old;
        struct sigaction sa {};
        sa.sa_handler = onForwardedSignal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = 0; // no SA_RESTART: a waitpid in progress returns EINTR
        ::sigaction(kSignals[i], &sa, nullptr);
    }
}

pid_t spawnChild(const std::vector<std::string>& argv, const std::vector<std::string>& env) {
    std::vector<std::string> args = argv, vars = env;
    for (char** e = environ; *e; ++e)
        vars.emplace_back(*e); // the added ones first: getenv finds them first
    std::vector<char*> cargv, cenv;
    for (std::string& a : args)
        cargv.push_back(a.data());
    cargv.push_back(nullptr);
    for (std::string& v : vars)
        cenv.push_back(v.data());
    cenv.push_back(nullptr);
    pid_t pid = 0;
    const int rc =
        ::posix_spawn(&pid, args[0].c_str(), nullptr, nullptr, cargv.data(), cenv.data());
    VEIL_CHECK(rc == 0, "cannot start '{}': {}", args[0], std::strerror(rc));
    for (auto& c : gChildren) {
        pid_t free = 0;
        if (c.compare_exchange_strong(free, pid)) break;
    }
    // A signal that came before the child was registered reaches it now.
    if (gSignal) ::kill(pid, gSignal);
    return pid;
}

std::vector<ChildExit> waitChildren(const std::vector<pid_t>& pids) {
    std::vector<ChildExit> out(pids.size());
    for (std::size_t i = 0; i < pids.size(); ++i) {
        int status = 0;
        pid_t r = -1;
        do {
            r = ::waitpid(pids[i], &status, 0);
        } while (r < 0 && errno == EINTR);
        for (auto& c : gChildren) {
            pid_t p = pids[i];
            if (c.compare_exchange_strong(p, 0)) break;
        }
        if (r < 0) {
            out[i].status = 127;
        } else if (WIFSIGNALED(status)) {
            out[i].signal = WTERMSIG(status);
        } else {
            out[i].status = WEXITSTATUS(status);
        }
    }
    return out;
}

int pendingSignal() { return gSignal; }

void dieOfSignal(int sig) {
    if (gCleanup) gCleanup();
    ::signal(sig, SIG_DFL);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, sig);
    ::sigprocmask(SIG_UNBLOCK, &set, nullptr);
    ::raise(sig);
    std::_Exit(128 + sig);
}

std::string signalName(int sig) {
    const char* d = ::strsignal(sig);
    return fmt::format("signal {} ({})", sig, d ? d : "unknown");
}

std::optional<std::filesystem::path> findOnPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        if (dir.empty()) continue;
        const std::filesystem::path candidate = std::filesystem::path(dir) / program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return std::nullopt;
}

ChildExit runProgram(const std::vector<std::string>& argv, const std::string& what) {
    std::vector<std::string> args = argv;
    std::vector<char*> cargv;
    for (std::string& a : args)
        cargv.push_back(a.data());
    cargv.push_back(nullptr);
    const pid_t pid = ::fork();
    VEIL_CHECK(pid >= 0, "cannot start {}", what);
    if (pid == 0) {
        ::execv(cargv[0], cargv.data());
        ::_exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    ChildExit e;
    if (WIFEXITED(status))
        e.status = WEXITSTATUS(status);
    else
        e.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    return e;
}

} // namespace veil::process
