// Replays the fuzzers' saved findings (tests/fuzz/regressions/<target>/) and their seed
// corpora (tests/fuzz/corpus/<target>/) through the entry points the libFuzzer targets call
// (tests/fuzz/fuzz_entries.h), in the ordinary build: every input must either load or end in
// veil::Error; any other exception fails the test, a crash or a hang fails the suite.
#include "fuzz/fuzz_entries.h"

#include "base/log.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kFuzzDir = fs::path(VEIL_SOURCE_DIR) / "tests" / "fuzz";

const veil::fuzz::Entry& entry(std::string_view name) {
    const auto all = veil::fuzz::entries();
    const auto it = std::find_if(all.begin(), all.end(),
                                 [&](const veil::fuzz::Entry& e) { return e.name == name; });
    if (it == all.end()) throw std::runtime_error("no fuzz entry " + std::string(name));
    return *it;
}

std::vector<fs::path> filesIn(const fs::path& dir) {
    std::vector<fs::path> files;
    if (fs::is_directory(dir))
        for (const fs::directory_entry& f : fs::directory_iterator(dir))
            if (f.is_regular_file()) files.push_back(f.path());
    std::sort(files.begin(), files.end());
    return files;
}

// Replays every file of `folder`/<target>/ and returns how many there were.
std::size_t replay(const std::string& target, const std::string& folder) {
    const veil::fuzz::Entry& e = entry(target);
    const std::vector<fs::path> files = filesIn(kFuzzDir / folder / target);
    const veil::log::Level saved = veil::log::level();
    veil::log::setLevel(veil::log::Level::Off); // hostile inputs warn a lot
    for (const fs::path& file : files) {
        std::ifstream in(file, std::ios::binary);
        const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                              std::istreambuf_iterator<char>()};
        SCOPED_TRACE(file.string());
        try {
            (void)e.run(bytes);
        } catch (const std::exception& ex) {
            ADD_FAILURE() << "not a veil::Error: " << ex.what();
        } catch (...) {
            ADD_FAILURE() << "a non-std exception escaped";
        }
    }
    veil::log::setLevel(saved);
    return files.size();
}

} // namespace

TEST(FuzzRegression, SceneFindingsAndSeedsLoadOrFailWithVeilError) {
    replay("scene", "regressions");
    EXPECT_GT(replay("scene", "corpus"), 0u);
}

TEST(FuzzRegression, VolumeFindingsAndSeedsLoadOrFailWithVeilError) {
    replay("volume", "regressions");
    EXPECT_GT(replay("volume", "corpus"), 0u);
}

TEST(FuzzRegression, MeshFindingsAndSeedsLoadOrFailWithVeilError) {
    replay("mesh", "regressions");
    EXPECT_GT(replay("mesh", "corpus"), 0u);
}

TEST(FuzzRegression, SuiteFindingsAndSeedsLoadOrFailWithVeilError) {
    replay("suite", "regressions");
    EXPECT_GT(replay("suite", "corpus"), 0u);
}

TEST(FuzzRegression, ResultsFindingsAndSeedsLoadOrFailWithVeilError) {
    replay("results", "regressions");
    EXPECT_GT(replay("results", "corpus"), 0u);
}

TEST(FuzzRegression, TimeFindingsAndSeedsLoadOrFailWithVeilError) {
    replay("time", "regressions");
    EXPECT_GT(replay("time", "corpus"), 0u);
}

TEST(FuzzRegression, FramesFindingsAndSeedsLoadOrFailWithVeilError) {
    replay("frames", "regressions");
    EXPECT_GT(replay("frames", "corpus"), 0u);
}

// The seeds made from the repository's scenes and the hand-written meshes are valid inputs:
// if they were rejected the fuzzers would spend their time on error paths only.
TEST(FuzzRegression, ValidSeedsAreAccepted) {
    const veil::log::Level saved = veil::log::level();
    veil::log::setLevel(veil::log::Level::Off);
    for (const auto& [target, name] :
         std::vector<std::pair<std::string, std::string>>{{"scene", "default.json"},
                                                          {"scene", "default-overrides"},
                                                          {"scene", "oit-glass-overrides"},
                                                          {"suite", "four-cases.json"},
                                                          {"suite", "minimal.json"},
                                                          {"results", "shard.json"},
                                                          {"results", "empty.json"},
                                                          {"mesh", "quad.obj"},
                                                          {"mesh", "quad-ascii.ply"},
                                                          {"mesh", "tri-binary.ply"},
                                                          {"mesh", "tri.gltf"},
                                                          {"mesh", "tri.glb"},
                                                          {"volume", "veil-small.vdb"},
                                                          {"volume", "torus01.vdb"},
                                                          {"time", "keys-linear.json"},
                                                          {"time", "catmull-turntable.json"},
                                                          {"time", "sequences.json"},
                                                          {"frames", "range-hashes"},
                                                          {"frames", "negative-unpadded"},
                                                          {"frames", "houdini"}}) {
        std::ifstream in(kFuzzDir / "corpus" / target / name, std::ios::binary);
        ASSERT_TRUE(in) << target << "/" << name;
        const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                              std::istreambuf_iterator<char>()};
        EXPECT_EQ(entry(target).run(bytes), veil::fuzz::Outcome::Accepted)
            << target << "/" << name << ": " << veil::fuzz::lastError();
    }
    veil::log::setLevel(saved);
}
