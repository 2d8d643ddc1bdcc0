// A progress line on stderr for long work: nothing for work that ends within the
// delay (2 s), then "veil: <label> 3.5 s" redrawn in place every half second on a terminal, or
// one line per second when stderr is not a terminal but --progress asked for it; a last
// "<label> done in 7.1 s" line when anything was shown. stdout is never touched.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace veil {

// Whether to show progress: --progress, or stderr is a terminal.
bool progressWanted(bool flag);

class ProgressTicker {
public:
    // The delay is 2 s unless $VEIL_PROGRESS_DELAY_S sets it (tests use 0).
    ProgressTicker(std::string label, bool enabled);
    ~ProgressTicker();
    ProgressTicker(const ProgressTicker&) = delete;
    ProgressTicker& operator=(const ProgressTicker&) = delete;

private:
    void run();

    std::string label_;
    bool terminal_ = false;
    double delay_ = 2.0;
    std::chrono::steady_clock::time_point start_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool done_ = false, shown_ = false;
    std::thread thread_;
};

} // namespace veil
