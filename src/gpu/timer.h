// Per-pass GPU times. GL_TIME_ELAPSED queries where the driver has a working timer; on
// software renderers (llvmpipe reads zero) each scope is bracketed by glFinish and timed on
// the CPU clock instead, which is what a pass costs there; the process's CPU time (all of
// the driver's threads) is recorded too, a measure that other processes on the same cores do
// not inflate (bench/vdb_compare.sh).
#pragma once

#include "gpu/objects.h"

#include <chrono>
#include <string>
#include <vector>

namespace veil::gpu {

struct PassTime {
    std::string name;
    double milliseconds = 0.0;
    double cpuMilliseconds = -1.0; // process CPU time over the scope (CpuFinish mode; else -1)
};

class GpuTimer {
public:
    enum class Mode { Query, CpuFinish };
    explicit GpuTimer(Mode mode) : mode_(mode) {}

    // Scopes may not nest (GL_TIME_ELAPSED queries cannot); the frame's passes are sequential.
    void begin(const std::string& name);
    void end();
    // Waits for the results of every scope since the last collect().
    std::vector<PassTime> collect();
    Mode mode() const { return mode_; }

private:
    struct Scope {
        std::string name;
        Query query{NoCreate};
        std::chrono::steady_clock::time_point start;
        double cpuMs = 0.0;
        double processStartMs = 0.0, processMs = -1.0;
    };
    Mode mode_;
    std::vector<Scope> scopes_;
    bool open_ = false;
};

// RAII scope: GpuTimer::begin in the constructor, end in the destructor.
class TimerScope {
public:
    TimerScope(GpuTimer& timer, const std::string& name) : timer_(timer) { timer_.begin(name); }
    ~TimerScope() { timer_.end(); }
    TimerScope(const TimerScope&) = delete;
    TimerScope& operator=(const TimerScope&) = delete;

private:
    GpuTimer& timer_;
};

} // namespace veil::gpu
