// A progress line on stderr for long work: nothing for work that ends within the
// delay (2 s), then "veil: <label> 3.5 s" redrawn in place every half second on a terminal, or
// one line per second when stderr is not a terminal but --progress asked for it; a last
// "<label> done in 7.1 s" line when anything was shown. stdout is never touched.
// Work deep inside a ticker's span (a cache baked before the first frame) names itself on the
// line with a ProgressNote: "veil: <label> 3.5 s: <note>, 40 %, about 5 s left".
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace veil {

// Whether to show progress: --progress, or stderr is a terminal.
bool progressWanted(bool flag);

// The note shown after the running ticker's label while it lives (one at a time, any thread):
// what is being done and the fraction done (set(); negative: unknown), from which the line
// estimates the time left. Without a ticker nothing is shown. A note made while another
// lives (a tile of a sweep, then the fog reference inside it) replaces it until it ends, and
// the other is shown again, with its fraction and start.
class ProgressNote {
public:
    explicit ProgressNote(std::string what);
    ~ProgressNote();
    ProgressNote(const ProgressNote&) = delete;
    ProgressNote& operator=(const ProgressNote&) = delete;
    void set(double fraction);

private:
    std::string outerWhat_;
    double outerFraction_ = -1.0;
    std::chrono::steady_clock::time_point outerStart_;
};

// The current note as the ticker shows it (", 40 %, about 5 s left" included), or "" (tests).
std::string progressNoteText();

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
