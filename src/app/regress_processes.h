// Child processes of `veil regress` (the --jobs shards, and the worker process that renders a
// shard's cases under a supervising process) and the signals that end them: SIGINT, SIGTERM
// and SIGHUP are passed on to the children, and the parent cleans up after them and then dies
// of the same signal (docs/regression.md "Interrupted and concurrent runs").
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace veil::app {

// Installs the handler (once). A signal with children running is passed on to them and
// remembered (pendingSignal); with none, the report lock file is removed and the process dies
// of it (after the temporaries of base/atomic_file.h are removed).
void installRegressSignalHandlers();

// Starts `argv` (argv[0] is the program) with `env` added to this process's environment.
pid_t spawnChild(const std::vector<std::string>& argv, const std::vector<std::string>& env);

struct ChildExit {
    int status = 0; // exit status when it exited
    int signal = 0; // the signal that ended it, 0 when it exited
};
// Waits for every child in `pids`, however long; the signals above arriving meanwhile are
// passed on to them (the wait goes on until they are gone).
std::vector<ChildExit> waitChildren(const std::vector<pid_t>& pids);

// The signal that arrived while children ran, 0 when none.
int pendingSignal();
// Removes the report lock file and dies of `sig`.
[[noreturn]] void dieOfSignal(int sig);

// "signal 11 (Segmentation fault)".
std::string signalName(int sig);

} // namespace veil::app
