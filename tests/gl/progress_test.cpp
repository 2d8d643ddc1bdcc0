// The progress line of `veil render`: on stderr only, only past the delay,
// only with --progress when stderr is not a terminal; stdout unchanged.
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

TEST(ProgressTest, StderrOnlyPastTheDelayAndOnlyWhenAsked) {
    const fs::path d = outputDir() / "progress";
    fs::create_directories(d);
    std::ofstream(d / "scene.json") << R"({
      "render": {"width": 48, "height": 32},
      "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0, 0]}],
      "lights": [{"type": "directional", "direction": [0, -1, 0]}],
      "materials": {"m": {"base_color": 0.5}},
      "objects": [{"shape": {"type": "box", "size": [1, 1, 1]}, "material": "m"}]
    })";
    const std::string render = veilExe() + " render '" + (d / "scene.json").string() + "' -o '" +
                               (d / "out.png").string() + "'";
    // stderr to a file (inside a subshell: runCommand adds 2>&1 for the whole line).
    const std::string err = (d / "stderr.txt").string();
    // Captured stderr is no terminal: nothing without --progress, even past the delay.
    CommandResult quiet = runCommand("(VEIL_PROGRESS_DELAY_S=0 " + render + " 2>'" + err + "')");
    ASSERT_EQ(quiet.exitCode, 0) << quiet.output;
    EXPECT_EQ(readTextFile(err), "");
    // --progress past the delay (0 s here; 2 s by default): the line and the final time.
    CommandResult shown =
        runCommand("(VEIL_PROGRESS_DELAY_S=0 " + render + " --progress 2>'" + err + "')");
    ASSERT_EQ(shown.exitCode, 0) << shown.output;
    const std::string progress = readTextFile(err);
    EXPECT_NE(progress.find("veil: rendering with blend "), std::string::npos) << progress;
    EXPECT_NE(progress.find("veil: rendering with blend done in "), std::string::npos) << progress;
    EXPECT_EQ(shown.output, quiet.output); // stdout untouched
    // Work that ends before the delay shows nothing.
    CommandResult fast =
        runCommand("(VEIL_PROGRESS_DELAY_S=60 " + render + " --progress 2>'" + err + "')");
    ASSERT_EQ(fast.exitCode, 0) << fast.output;
    EXPECT_EQ(readTextFile(err), "");
}

} // namespace veil::test
