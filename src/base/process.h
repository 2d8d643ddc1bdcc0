// Child processes and the signals that end a long run (POSIX).
//
// Two ways a command meets SIGINT / SIGTERM:
//   StopOnSignal   a loop of steps (`veil render --frames`): the first signal asks it to stop
//                  after the current step, a second one ends the process;
//   forwardSignals a parent of child processes (`veil regress --jobs`, its worker): SIGINT,
//                  SIGTERM and SIGHUP are passed on to the children, and the parent cleans up
//                  after them and then dies of the same signal.
// Both hand a second or child-less signal to the handler that was there before (the
// temporaries of base/atomic_file.h are removed, then the process dies of it).
#pragma once

#include <sys/types.h>

#include <atomic>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace veil::process {

// While it lives, the first SIGINT or SIGTERM sets stopRequested() (and signal()); a second
// one gets the previous handler. The previous handlers come back when it ends.
class StopOnSignal {
public:
    StopOnSignal();
    ~StopOnSignal();
    StopOnSignal(const StopOnSignal&) = delete;
    StopOnSignal& operator=(const StopOnSignal&) = delete;

    // The flag a loop polls (also after the guard ended).
    static const std::atomic<bool>& stopFlag();
    static int signal(); // the signal that set it, 0 when none
};

// Installs the forwarding handler for SIGINT, SIGTERM and SIGHUP (once). A signal with
// children running is passed on to them and remembered (pendingSignal); with none,
// `cleanup` runs (it must be async-signal-safe) and the process dies of it.
void forwardSignals(void (*cleanup)());

// Starts `argv` (argv[0] is the program) with `env` added to this process's environment; the
// forwarding handler reaches it.
pid_t spawnChild(const std::vector<std::string>& argv, const std::vector<std::string>& env);

struct ChildExit {
    int status = 0; // exit status when it exited
    int signal = 0; // the signal that ended it, 0 when it exited
};
// Waits for every child in `pids`, however long; signals arriving meanwhile are passed on to
// them (the wait goes on until they are gone).
std::vector<ChildExit> waitChildren(const std::vector<pid_t>& pids);

// The signal that arrived while children ran, 0 when none.
int pendingSignal();
// Runs forwardSignals' cleanup and dies of `sig`.
[[noreturn]] void dieOfSignal(int sig);

// "signal 11 (Segmentation fault)".
std::string signalName(int sig);

// The executable `program` in a folder of $PATH, nullopt when there is none.
std::optional<std::filesystem::path> findOnPath(const std::string& program);

// Runs `argv` (argv[0] a path) to its end in a forked child; exit status 127 when it cannot
// be executed. Throws veil::Error "cannot start <what>" when no process can be made.
ChildExit runProgram(const std::vector<std::string>& argv, const std::string& what);

} // namespace veil::process
