// libFuzzer's two hooks around one entry of fuzz_entries.h, chosen at compile time by
// VEIL_FUZZ_ENTRY (tests/fuzz/CMakeLists.txt builds this file once per target).
#include "fuzz/fuzz_entries.h"

#include "base/log.h"

#include <cstdio>
#include <cstdlib>

#ifndef VEIL_FUZZ_ENTRY
#error "VEIL_FUZZ_ENTRY must name an entry of veil::fuzz::entries(), e.g. \"scene\""
#endif

namespace {

veil::fuzz::Outcome (*gRun)(std::span<const std::uint8_t>) = nullptr;
bool gVerbose = false; // VEIL_FUZZ_VERBOSE=1: one line per input, for checking seeds

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // Warnings for every odd input would be most of the output and slow the run down.
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
