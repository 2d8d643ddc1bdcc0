// Helpers shared by the test suites: paths, files, error messages, image comparison, running
// the veil command.
#pragma once

#include "base/error.h"
#include "base/image.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace veil::test {

std::filesystem::path sourceDir(); // repository root
std::filesystem::path dataDir();   // datasets/third_party (third-party data, in the repository)
std::filesystem::path outputDir(); // build/test-output, created on demand
// outputDir() / name, created on demand (kept between runs).
std::filesystem::path outputSubdir(const std::string& name);
// outputDir() / group / name, emptied first.
std::filesystem::path freshOutputDir(const std::string& group, const std::string& name);
// Writes `text` to `path` as bytes and returns the path; the whole file as a string.
std::filesystem::path writeTextFile(const std::filesystem::path& path, const std::string& text);
std::string readTextFile(const std::filesystem::path& path);
// The file parsed as JSON (nlohmann::json::parse_error if it is not).
nlohmann::json readJson(const std::filesystem::path& path);

// The message of the veil::Error that f() throws; empty when it throws none.
template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

// The path in single quotes for the shell, a quote inside it written as '\''.
std::string shellQuote(const std::filesystem::path& path);

struct ImageDiff {
    double maxAbs = 0.0; // largest per-channel absolute difference
    double rmse = 0.0;   // root mean square over all compared channels
};

// Compares the first `channels` channels; sizes must match (else maxAbs = rmse = inf).
ImageDiff compareImages(const ImageF& a, const ImageF& b, int channels = 3);

// Writes <name>-render.exr, <name>-reference.exr and <name>-diff.exr (|a-b|) into outputDir()
// and returns the folder, for a failing image test to point at.
std::string writeFailureImages(const std::string& name, const ImageF& render,
                               const ImageF& reference);

struct CommandResult {
    int exitCode = -1;
    std::string output; // stdout and stderr together
};
// Runs a shell command line, capturing its output.
CommandResult runCommand(const std::string& commandLine);
// Path of the built veil executable.
std::string veilExe();

// Wall-clock bounds of the "done quickly" guards (an algorithm that once took minutes) are set
// for an optimized build; the sanitizer build (ASan at -O1) runs the same library code about
// three times slower, so a guard multiplies its bound by this (1 otherwise). The old slow
// paths are slower by the same factor there, so a guard still tells them apart. GCC defines
// __SANITIZE_ADDRESS__; clang 14 reports ASan through __has_feature only.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VEIL_TEST_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define VEIL_TEST_UNDER_ASAN 1
#endif
constexpr double kSlowBuildFactor =
#if defined(VEIL_TEST_UNDER_ASAN)
    3.0;
#else
    1.0;
#endif

} // namespace veil::test
