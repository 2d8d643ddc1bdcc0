// The entry points of the libFuzzer targets (docs/fuzzing.md), shared by the fuzzer
// executables and by tests/unit/fuzz_regression_test.cpp, which replays the saved findings
// of tests/fuzz/regressions/<target>/ through the very same functions.
//
// Each entry takes the raw input bytes, treats veil::Error as the expected outcome of a bad
// input and lets everything else escape: another exception, a crash or a sanitizer report
// is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace veil::fuzz {

enum class Outcome { Accepted, Rejected }; // Rejected: the input threw veil::Error

// Scene JSON with command-line overrides. The input is split at NUL bytes: the text before
// the first NUL is the scene document, every following piece one `key=value` override (as
// argv would give them, so they cannot hold a NUL either; a trailing NUL adds none). Runs
// parseJsonText, applyOverrides and parseScene as loadScene does, with an empty folder as
// the scene's base so relative mesh paths are missing files, never the repository's.
Outcome sceneEntry(std::span<const std::uint8_t> input);

// OpenVDB loading: the bytes become a .vdb file; listGrids, loadDensityGrid of a name the
// file does not hold, then of the grids it lists (at most 4) until one loads.
Outcome volumeEntry(std::span<const std::uint8_t> input);

// Mesh loading through assimp: the first byte picks the extension (.ply .obj .gltf .glb,
// by its value modulo 4), the rest becomes the file handed to loadMeshFile.
Outcome meshEntry(std::span<const std::uint8_t> input);

// Regression suites: the bytes become suite.json in an empty folder (its scenes are missing
// files, never the repository's) and go through regress::loadSuite.
Outcome suiteEntry(std::span<const std::uint8_t> input);

// The results.json reader of `veil regress --merge`: the bytes become a shard folder's
// results.json and go through regress::readReport.
Outcome resultsEntry(std::span<const std::uint8_t> input);

// The scene's time block and keys over frames: the bytes are a scene document (in a folder of
// a few empty sequence files: seq.0001.vdb, f_1.vdb, ...) through parseAnimatedScene, then
// sceneFrameRange, and at its ends, middle, default frame and one frame past each end the
// cameras' checks, cameras and lights between keys, volumeFrames and sceneAtFrame (a missing
// file at one frame is a veil::Error the others go on after), then the range's frames().
Outcome timeEntry(std::span<const std::uint8_t> input);

// Frame ranges and sequence patterns: the bytes up to the first NUL are a --frames text
// (parseFrameRange, frames()), the next piece a file pattern (parseFilePattern), the rest file
// names for FilePattern::frameOf. A file name fileFor() writes for a frame >= 0 must read back
// as that frame; the pattern is also matched in a folder of a few files (existingFrames,
// missingFrames, resolveSequenceFrame over the range).
Outcome framesEntry(std::span<const std::uint8_t> input);

struct Entry {
    std::string_view name; // the target's name: veil_fuzz_<name>, corpus/<name>/
    Outcome (*run)(std::span<const std::uint8_t>);
};

// scene, volume, mesh, suite, results, time, frames.
std::span<const Entry> entries();

// The message of the veil::Error behind the last Outcome::Rejected (for VEIL_FUZZ_VERBOSE
// and the regression test's failure messages).
const std::string& lastError();

} // namespace veil::fuzz
