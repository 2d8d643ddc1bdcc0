// Small things a first hour with `veil` ran into: a scene file with comments as plain JSON
// (`veil info --json`).
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

} // namespace veil::test
