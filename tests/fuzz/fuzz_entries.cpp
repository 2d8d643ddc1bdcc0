#include "fuzz/fuzz_entries.h"

#include "base/error.h"
#include "grid/density_grid.h"
#include "regress/report.h"
#include "regress/suite.h"
#include "scene/json_text.h"
#include "scene/mesh.h"
#include "scene/scene.h"
#include "scene/timeline.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
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

// A folder of `scratchDir()` holding empty files of a few sequences (their content is never
// read): the time and frames targets find, hold and miss frames there.
const fs::path& sequenceDir(const std::string& name) {
    static std::vector<std::pair<std::string, fs::path>> made;
    for (const auto& [n, dir] : made)
        if (n == name) return dir;
    const fs::path dir = scratchDir() / name;
    fs::create_directories(dir);
    for (const char* file :
         {"seq.0001.vdb", "seq.0002.vdb", "seq.0004.vdb", "seq.0010.vdb", "f_1.vdb", "f_3.vdb",
          "f_007.vdb", "f.$F.exr", "s.-001.vdb", "long.000000000012.vdb"})
        std::ofstream(dir / file) << "x";
    made.emplace_back(name, dir);
    return made.back().second;
}

// Pieces of the input between NUL bytes (a trailing NUL adds none).
std::vector<std::string_view> nulPieces(std::span<const std::uint8_t> input) {
    std::string_view rest(reinterpret_cast<const char*>(input.data()), input.size());
    std::vector<std::string_view> pieces;
    while (!rest.empty()) {
        const std::size_t end = rest.find('\0');
        pieces.push_back(rest.substr(0, end));
        rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    }
    return pieces;
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

Outcome timeEntry(std::span<const std::uint8_t> input) {
    const std::string_view text(reinterpret_cast<const char*>(input.data()), input.size());
    const fs::path& base = sequenceDir("time-base");
    return expectOnlyVeilErrors([&] {
        const nlohmann::json doc = scene::parseJsonText(text, "<fuzz>");
        const scene::AnimatedScene s = scene::parseAnimatedScene(doc, base);
        (void)s.timeline.animated();
        const scene::FrameRange range = scene::sceneFrameRange(s.timeline);
        (void)scene::frameCountProblem(range, "the scene's frames");
        // The range's ends and middle, the default frame and one frame past each end; the
        // keys between frames too (cameraAtFrame and lightAtFrame take any time).
        const long long probes[] = {range.first,
                                    range.last,
                                    ((long long)range.first + range.last) / 2,
                                    scene::defaultFrame(s.timeline),
                                    (long long)range.first - 1,
                                    (long long)range.last + 1};
        for (const long long p : probes) {
            if (p < INT_MIN || p > INT_MAX) continue;
            const int frame = int(p);
            for (std::size_t i = 0; i < s.scene.cameras.size(); ++i) {
                (void)scene::cameraProblemAtFrame(s.scene.cameras[i], s.timeline.cameras[i], frame);
                (void)scene::cameraAtFrame(s.scene.cameras[i], s.timeline.cameras[i], frame + 0.37);
            }
            for (std::size_t i = 0; i < s.scene.lights.size(); ++i)
                (void)scene::lightAtFrame(s.scene.lights[i], s.timeline.lights[i], frame + 0.37);
            try {
                (void)scene::volumeFrames(s, frame);
                (void)scene::sceneAtFrame(s, frame);
            } catch (const veil::Error&) {
                // A missing file or an unrenderable camera at this frame; the others go on.
            }
        }
        const std::vector<int> frames = range.frames("the scene's frames");
        if (static_cast<long long>(frames.size()) != range.count())
            throw std::logic_error("FrameRange::frames() disagrees with count()");
    });
}

Outcome framesEntry(std::span<const std::uint8_t> input) {
    const std::vector<std::string_view> pieces = nulPieces(input);
    const fs::path& dir = sequenceDir("frames-dir");
    return expectOnlyVeilErrors([&] {
        std::string refused;
        std::vector<int> frames;
        try {
            const scene::FrameRange range =
                scene::parseFrameRange(std::string(pieces.empty() ? "" : pieces[0]));
            frames = range.frames();
            if (frames.empty() || frames.front() != range.first || frames.back() > range.last ||
                static_cast<long long>(frames.size()) != range.count())
                throw std::logic_error("parseFrameRange: frames() outside first..last");
        } catch (const veil::Error& e) {
            refused = e.what();
        }
        if (pieces.size() < 2) {
            if (!refused.empty()) throw Error(refused);
            return;
        }
        const std::optional<scene::FilePattern> pattern =
            scene::parseFilePattern(fs::path(std::string(pieces[1])));
        if (!pattern) return;
        // A file name the pattern writes for a frame reads back as that frame (frame numbers
        // of files are not negative).
        std::vector<int> probes = {0, 1, 7, 99999, 123456789, INT_MAX};
        if (!frames.empty()) probes.insert(probes.end(), {frames.front(), frames.back()});
        for (const int f : probes) {
            const std::string name = pattern->fileFor(f).filename().string();
            if (f >= 0 && pattern->frameOf(name) != f)
                throw std::logic_error("frameOf(fileFor(" + std::to_string(f) + ")) is not " +
                                       std::to_string(f) + ": '" + name + "'");
        }
        for (std::size_t i = 2; i < pieces.size(); ++i)
            (void)pattern->frameOf(std::string(pieces[i]));
        // The same pattern in a folder of a few files: each frame found has its file.
        scene::FilePattern here = *pattern;
        here.folder = dir;
        for (const int f : scene::existingFrames(here))
            if (!fs::is_regular_file(here.fileFor(f)))
                throw std::logic_error("existingFrames() found a frame without its file");
        if (!frames.empty()) {
            scene::FileSequence seq;
            seq.pattern = here;
            seq.first = frames.front();
            seq.last = frames.back();
            seq.step = frames.size() > 1 ? frames[1] - frames[0] : 1;
            seq.holdMissing = true;
            seq.before = scene::Outside::Loop;
            seq.after = scene::Outside::Blank;
            (void)scene::missingFrames(seq, 8);
            for (const long long f : {(long long)frames.front() - 1, (long long)frames.front(),
                                      (long long)frames.back(), (long long)frames.back() + 1}) {
                if (f < INT_MIN || f > INT_MAX) continue;
                try {
                    (void)scene::resolveSequenceFrame(seq, int(f), "fuzz");
                } catch (const veil::Error&) {
                    // No file of the sequence exists.
                }
            }
        }
        if (!refused.empty()) throw Error(refused);
    });
}

const std::string& lastError() { return gLastError; }

std::span<const Entry> entries() {
    static constexpr std::array<Entry, 7> kEntries = {
        Entry{"scene", sceneEntry},  Entry{"volume", volumeEntry},   Entry{"mesh", meshEntry},
        Entry{"suite", suiteEntry},  Entry{"results", resultsEntry}, Entry{"time", timeEntry},
        Entry{"frames", framesEntry}};
    return kEntries;
}

} // namespace veil::fuzz
