#include "fuzz/fuzz_entries.h"

#include "base/error.h"
#include "regress/report.h"
#include "regress/suite.h"
#include "scene/json_text.h"
#include "scene/mesh.h"
#include "scene/scene.h"
#include "grid/density_grid.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace veil::fuzz {

namespace fs = std::filesystem;

namespace {

// One folder per process, made on first use and removed at exit: parallel fuzzing jobs
// (-jobs=N) and ctest never share a file. Only the fuzz inputs are written there. The path
// is never destroyed, so the atexit handler cannot outlive it.
const fs::path& scratchDir() {
    static const fs::path* dir = [] {
        std::string pattern = (fs::temp_directory_path() / "veil-fuzz.XXXXXX").string();
        if (!mkdtemp(pattern.data())) {
            std::perror("veil fuzz: mkdtemp");
            std::abort();
        }
        auto* made = new fs::path(pattern);
        std::atexit([] {
            std::error_code ec;
            fs::remove_all(scratchDir(), ec);
        });
        return made;
    }();
    return *dir;
}

fs::path writeInput(const std::string& name, std::span<const std::uint8_t> bytes) {
    const fs::path path = scratchDir() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
        std::fprintf(stderr, "veil fuzz: cannot write %s\n", path.string().c_str());
        std::abort(); // not a finding of the code under test, but never silently skip inputs
    }
    return path;
}

std::string gLastError;

template <typename F>
Outcome expectOnlyVeilErrors(F&& body) {
    gLastError.clear();
    try {
        body();
        return Outcome::Accepted;
    } catch (const veil::Error& e) {
        gLastError = e.what();
        return Outcome::Rejected;
    }
}

} // namespace

Outcome sceneEntry(std::span<const std::uint8_t> input) {
    const std::string_view all(reinterpret_cast<const char*>(input.data()), input.size());
    const std::size_t nul = all.find('\0');
    const std::string_view text = all.substr(0, nul);
    std::vector<std::string> overrides;
    if (nul != std::string_view::npos) {
        std::string_view rest = all.substr(nul + 1);
        while (!rest.empty()) {
            const std::size_t end = rest.find('\0');
            overrides.emplace_back(rest.substr(0, end));
            rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
        }
    }
    static const fs::path base = [] {
        fs::path dir = scratchDir() / "scene-base";
        fs::create_directories(dir);
        return dir;
    }();
    return expectOnlyVeilErrors([&] {
        nlohmann::json doc = scene::parseJsonText(text, "<fuzz>");
        scene::applyOverrides(doc, overrides);
        const scene::Scene parsed = scene::parseScene(doc, base);
        (void)parsed;
    });
}

Outcome volumeEntry(std::span<const std::uint8_t> input) {
    const fs::path path = writeInput("input.vdb", input);
    return expectOnlyVeilErrors([&] {
        const std::vector<volume::GridSummary> grids = volume::listGrids(path);
        try {
            (void)volume::loadDensityGrid(path, "veil-fuzz-no-such-grid");
        } catch (const veil::Error&) {
            // The expected outcome: the message lists the file's grids.
        }
        // Accepted when one grid loads; a vector or empty grid is refused and the next tried.
        std::string refused = "no grids";
        for (std::size_t i = 0; i < std::min<std::size_t>(grids.size(), 4); ++i) {
            try {
                (void)volume::loadDensityGrid(path, grids[i].name);
                return;
            } catch (const veil::Error& e) {
                refused = e.what();
            }
        }
        throw Error(refused);
    });
}

Outcome meshEntry(std::span<const std::uint8_t> input) {
    if (input.empty()) return expectOnlyVeilErrors([] { throw Error("empty input"); });
    static constexpr std::array<const char*, 4> kExtensions = {".ply", ".obj", ".gltf", ".glb"};
    const fs::path path = writeInput(
        std::string("input") + kExtensions[input[0] % kExtensions.size()], input.subspan(1));
    return expectOnlyVeilErrors([&] { (void)scene::loadMeshFile(path); });
}

// The one scene file beside the fuzzed suite, so suites naming "scene.json" can be accepted.
constexpr const char* kSuiteScene = R"({"cameras": [{"name": "c", "position": [0, 0, 4]}],
 "materials": {"m": {"alpha": 0.5}},
 "objects": [{"shape": {"type": "sphere", "radius": 0.5}, "material": "m"}]})";

Outcome suiteEntry(std::span<const std::uint8_t> input) {
    static const bool sceneWritten = [] {
        const std::string_view text = kSuiteScene;
        writeInput("scene.json", {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
        return true;
    }();
    (void)sceneWritten;
    const fs::path path = writeInput("suite.json", input);
    return expectOnlyVeilErrors([&] { (void)regress::loadSuite(path, false); });
}

Outcome resultsEntry(std::span<const std::uint8_t> input) {
    static const fs::path shard = [] {
        fs::path dir = scratchDir() / "shard";
        fs::create_directories(dir);
        return dir;
    }();
    writeInput("shard/results.json", input);
    return expectOnlyVeilErrors([&] { (void)regress::readReport(shard); });
}

const std::string& lastError() { return gLastError; }

std::span<const Entry> entries() {
    static constexpr std::array<Entry, 5> kEntries = {
        Entry{"scene", sceneEntry}, Entry{"volume", volumeEntry}, Entry{"mesh", meshEntry},
        Entry{"suite", suiteEntry}, Entry{"results", resultsEntry}};
    return kEntries;
}

} // namespace veil::fuzz
