#include "app/regress_processes.h"

#include "base/error.h"
#include "regress/report_folder.h"

#include <fmt/format.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>

extern char** environ;

namespace veil::app {

namespace {

volatile sig_atomic_t g_signal = 0;
std::array<std::atomic<pid_t>, 128> g_children{};
struct sigaction g_previous[3] = {};
constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void onRegressSignal(int sig) {
    g_signal = sig;
    bool children = false;
    for (auto& c : g_children)
        if (const pid_t p = c.load(); p > 0) {
            ::kill(p, sig);
            children = true;
        }
    if (children) return; // the parent's wait ends, it cleans up and calls dieOfSignal
    if (const char* lock = regress::lockFileForSignals(); lock[0]) ::unlink(lock);
    for (int i = 0; i < 3; ++i)
        if (kSignals[i] == sig) {
            struct sigaction dfl {};
            dfl.sa_handler = SIG_DFL;
            ::sigaction(sig, &dfl, nullptr);
            // The previous handler (temporaries of base/atomic_file.h) raises the signal again,
            // which the default action then delivers once this handler returns.
            if (g_previous[i].sa_handler != SIG_DFL && g_previous[i].sa_handler != SIG_IGN)
                g_previous[i].sa_handler(sig);
            else
                ::raise(sig);
        }
}

} // namespace

void installRegressSignalHandlers() {
    static bool installed = false;
    if (installed) return;
    installed = true;
    for (int i = 0; i < 3; ++i) {
        struct sigaction old {};
        if (::sigaction(kSignals[i], nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
        g_previous[i] = old;
        struct sigaction sa {};
        sa.sa_handler = onRegressSignal;
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
    for (auto& c : g_children) {
        pid_t free = 0;
        if (c.compare_exchange_strong(free, pid)) break;
    }
    // A signal that came before the child was registered reaches it now.
    if (g_signal) ::kill(pid, g_signal);
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
        for (auto& c : g_children) {
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

int pendingSignal() { return g_signal; }

void dieOfSignal(int sig) {
    if (const char* lock = regress::lockFileForSignals(); lock[0]) ::unlink(lock);
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

} // namespace veil::app
