#include "gpu/timer.h"

#include "base/error.h"

#include <ctime>

namespace veil::gpu {

namespace {
double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}
} // namespace

void GpuTimer::begin(const std::string& name) {
    VEIL_CHECK(!open_, "GPU timer scope '{}' opened inside another", name);
    open_ = true;
    Scope scope;
    scope.name = name;
    if (mode_ == Mode::Query) {
        scope.query = Query(GL_TIME_ELAPSED);
        glBeginQuery(GL_TIME_ELAPSED, scope.query.id());
    } else {
        glFinish();
        scope.start = std::chrono::steady_clock::now();
        scope.processStartMs = processCpuMs();
    }
    scopes_.push_back(std::move(scope));
}

void GpuTimer::end() {
    VEIL_CHECK(open_, "GPU timer end() without begin()");
    open_ = false;
    Scope& scope = scopes_.back();
    if (mode_ == Mode::Query) {
        glEndQuery(GL_TIME_ELAPSED);
    } else {
        glFinish();
        scope.cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                                scope.start)
                          .count();
        scope.processMs = processCpuMs() - scope.processStartMs;
    }
}

std::vector<PassTime> GpuTimer::collect() {
    VEIL_CHECK(!open_, "GPU timer collect() inside an open scope");
    std::vector<PassTime> times;
    times.reserve(scopes_.size());
    for (const Scope& scope : scopes_) {
        const double ms = mode_ == Mode::Query ? scope.query.result() * 1e-6 : scope.cpuMs;
        times.push_back({scope.name, ms, scope.processMs});
    }
    scopes_.clear();
    return times;
}

} // namespace veil::gpu
