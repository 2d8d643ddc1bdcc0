#include "base/progress.h"

#include <cstdio>
#include <cstdlib>
#include <unistd.h>

namespace veil {

namespace {

struct Note {
    std::mutex mutex;
    std::string what;
    double fraction = -1.0;
    std::chrono::steady_clock::time_point start;
};

Note& note() {
    static Note n;
    return n;
}

} // namespace

ProgressNote::ProgressNote(std::string what) {
    Note& n = note();
    std::lock_guard lock(n.mutex);
    outerWhat_ = std::move(n.what);
    outerFraction_ = n.fraction;
    outerStart_ = n.start;
    n.what = std::move(what);
    n.fraction = -1.0;
    n.start = std::chrono::steady_clock::now();
}

ProgressNote::~ProgressNote() {
    Note& n = note();
    std::lock_guard lock(n.mutex);
    n.what = std::move(outerWhat_);
    n.fraction = outerFraction_;
    n.start = outerStart_;
}

void ProgressNote::set(double fraction) {
    Note& n = note();
    std::lock_guard lock(n.mutex);
    n.fraction = fraction;
}

std::string progressNoteText() {
    Note& n = note();
    std::lock_guard lock(n.mutex);
    if (n.what.empty()) return {};
    std::string s = n.what;
    if (n.fraction > 0.0 && n.fraction <= 1.0) {
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - n.start).count();
        const double left = elapsed * (1.0 - n.fraction) / n.fraction;
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, ", %.0f %%, about %.0f s left", 100.0 * n.fraction,
                      left);
        s += buffer;
    }
    return s;
}

bool progressWanted(bool flag) { return flag || ::isatty(STDERR_FILENO) == 1; }

ProgressTicker::ProgressTicker(std::string label, bool enabled)
    : label_(std::move(label)), terminal_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {
    if (!enabled) return;
    if (const char* d = std::getenv("VEIL_PROGRESS_DELAY_S")) {
        char* end = nullptr;
        const double v = std::strtod(d, &end);
        if (end != d && v >= 0.0 && v < 1e6) delay_ = v;
    }
    thread_ = std::thread([this] { run(); });
}

ProgressTicker::~ProgressTicker() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        done_ = true;
    }
    wake_.notify_all();
    thread_.join();
    if (shown_) {
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        std::fprintf(stderr, "%sveil: %s done in %.1f s\n", terminal_ ? "\r\033[K" : "",
                     label_.c_str(), s);
        std::fflush(stderr);
    }
}

void ProgressTicker::run() {
    std::unique_lock lock(mutex_);
    auto next = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>(delay_));
    const auto period = std::chrono::milliseconds(terminal_ ? 500 : 1000);
    while (!wake_.wait_until(lock, next, [this] { return done_; })) {
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        // On a terminal the line is redrawn in place; in a log each tick is its own line.
        const std::string n = progressNoteText();
        std::fprintf(stderr, terminal_ ? "\r\033[Kveil: %s %.1f s%s%s" : "veil: %s %.1f s%s%s\n",
                     label_.c_str(), s, n.empty() ? "" : ": ", n.c_str());
        std::fflush(stderr);
        shown_ = true;
        next += period;
    }
}

} // namespace veil
