// libFuzzer's two hooks around one entry of fuzz_entries.h, chosen at compile time by
// VEIL_FUZZ_ENTRY (tests/fuzz/CMakeLists.txt builds this file once per target).
#include "fuzz/fuzz_entries.h"

#include "base/log.h"

#include <sanitizer/common_interface_defs.h>

#include <pthread.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>

#ifndef VEIL_FUZZ_ENTRY
#error "VEIL_FUZZ_ENTRY must name an entry of veil::fuzz::entries(), e.g. \"scene\""
#endif

namespace {

veil::fuzz::Outcome (*gRun)(std::span<const std::uint8_t>) = nullptr;
bool gVerbose = false; // VEIL_FUZZ_VERBOSE=1: one line per input, for checking seeds

// The VDB loader reads a file first in a forked child so that a crash inside OpenVDB
// becomes a veil::Error (src/grid/vdb_file.cpp). The child inherits libFuzzer's death
// callback and signal handlers, which would save the input as a crash of the fuzzer; in a
// child the crash is the loader's expected, contained outcome, so it ends by the signal.
void plainCrashesInChild() {
    __sanitizer_set_death_callback(nullptr);
    for (int sig : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL})
        std::signal(sig, SIG_DFL);
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // Warnings for every odd input would be most of the output and slow the run down.
    pthread_atfork(nullptr, nullptr, plainCrashesInChild);
    gVerbose = std::getenv("VEIL_FUZZ_VERBOSE") != nullptr;
    veil::log::setLevel(gVerbose ? veil::log::Level::Warn : veil::log::Level::Off);
    for (const veil::fuzz::Entry& e : veil::fuzz::entries())
        if (e.name == VEIL_FUZZ_ENTRY) gRun = e.run;
    if (!gRun) {
        std::fprintf(stderr, "veil fuzz: no entry named %s\n", VEIL_FUZZ_ENTRY);
        std::abort();
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const veil::fuzz::Outcome outcome = gRun(std::span<const std::uint8_t>(data, size));
    if (gVerbose)
        std::fprintf(stderr, "veil fuzz: %zu bytes %s%s\n", size,
                     outcome == veil::fuzz::Outcome::Accepted ? "accepted" : "rejected: ",
                     veil::fuzz::lastError().c_str());
    return 0;
}
