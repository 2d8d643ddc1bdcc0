// Small things a first hour with `veil` ran into: a scene file with comments as plain JSON
// (`veil info --json`), the shipped default scene's floor warned about once, and the
// progress line of `--shadows all` naming each tile with its technique and k/N.
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

const std::string kCommented = R"({
  // a comment json.load refuses
  "render": {"width": 24, "height": 16, "shadows": {"type": "moment"}},
  /* a block comment */
  "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0, 0]}],
  "lights": [{"type": "spot", "position": [0, 3, 1], "target": [0, 0, 0], "shadows": true}],
  "materials": {"m": {"base_color": 0.5}},
  "objects": [{"shape": {"type": "box", "size": [1, 1, 1]}, "material": "m"},
              {"shape": {"type": "plane", "size": [4, 4]}, "material": "m"}]
})";

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
        ++n;
    return n;
}

} // namespace

TEST(FirstHourCliTest, InfoJsonPrintsTheSceneAsPlainJson) {
    const fs::path d = freshOutputDir("first_hour", "info_json");
    const fs::path scene = writeTextFile(d / "s.json", kCommented);
    const CommandResult r = runCommand(veilExe() + " info " + shellQuote(scene) + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // Strict JSON (nlohmann without ignore_comments), equal to the document.
    const nlohmann::json plain = nlohmann::json::parse(r.output);
    EXPECT_EQ(plain, nlohmann::json::parse(kCommented, nullptr, true, true));
    // And what the docs promise: Python's json.load reads it.
    const CommandResult py = runCommand(veilExe() + " info " + shellQuote(scene) +
                                        " --json | python3 -c 'import json, sys; "
                                        "print(json.load(sys.stdin)[\"render\"][\"width\"])'");
    EXPECT_EQ(py.exitCode, 0) << py.output;
    EXPECT_EQ(py.output, "24\n");
    // A .vdb is refused with one line naming it.
    const CommandResult vdb = runCommand(
        veilExe() + " info " + shellQuote(dataDir() / "vdb-sphere-fog/sphere.vdb") + " --json");
    EXPECT_EQ(vdb.exitCode, 1) << vdb.output;
    EXPECT_NE(vdb.output.find("--json prints a scene file as plain JSON; '"), std::string::npos)
        << vdb.output;
}

// Shadow volumes extrude an open mesh triangle by triangle and say so, once: the default
// scene's floor (a plane) was named twice, once per frame the renderer built it for.
TEST(FirstHourCliTest, DefaultScenesOpenFloorIsNamedOnce) {
    const fs::path d = freshOutputDir("first_hour", "floor");
    const CommandResult r = runCommand(
        veilExe() + " render " + shellQuote(sourceDir() / "datasets/scenes/default.json") +
        " --width 32 --height 18 --shadows volume -o " + shellQuote(d / "default.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(count(r.output, "mesh 'plane' is not a closed 2-manifold"), 1u) << r.output;
}

// `--shadows all`: each tile's progress line names its shadow technique and its place.
TEST(FirstHourCliTest, ShadowSweepProgressNamesEachTile) {
    const fs::path d = freshOutputDir("first_hour", "sweep");
    const fs::path scene = writeTextFile(d / "s.json", kCommented);
    const std::string err = (d / "stderr.txt").string();
    const CommandResult r = runCommand("(VEIL_PROGRESS_DELAY_S=0 " + veilExe() + " render " +
                                       shellQuote(scene) + " --shadows all --progress -o " +
                                       shellQuote(d / "all.png") + " 2>'" + err + "')");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string progress = readTextFile(err);
    EXPECT_NE(progress.find("veil: rendering with blend, shadows reference "), std::string::npos)
        << progress;
    EXPECT_NE(progress.find(": tile 1/"), std::string::npos) << progress;
    EXPECT_NE(progress.find(", shadows moment "), std::string::npos) << progress;
    EXPECT_NE(progress.find(": shadows moment"), std::string::npos) << progress;
}

} // namespace veil::test
