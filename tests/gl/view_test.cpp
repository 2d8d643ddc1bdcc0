// The viewer and the renderer produce the same image for the same scene, camera
// and settings. The viewer runs in a real GLFW window on a virtual X display (Xvfb).
#include "io/image_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

namespace veil::test {

namespace fs = std::filesystem;

TEST(ViewTest, ViewerScreenshotEqualsHeadlessRender) {
    ASSERT_EQ(runCommand("command -v xvfb-run").exitCode, 0)
        << "xvfb-run missing: scripts/install-deps.sh installs it";
    const fs::path scene = sourceDir() / "tests/regression/scenes/golden_basic.json";
    const fs::path viewed = outputDir() / "view-screenshot.png";
    const fs::path rendered = outputDir() / "view-render.png";
    fs::remove(viewed);
    fs::remove(rendered);
    CommandResult r =
        runCommand("xvfb-run -a -s '-screen 0 640x480x24' " + veilExe() + " view '" +
                   scene.string() + "' --frames 3 --screenshot '" + viewed.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = runCommand(veilExe() + " render '" + scene.string() + "' -o '" + rendered.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageF a = io::readImage(viewed), b = io::readImage(rendered);
    const ImageDiff d = compareImages(a, b);
    // Same driver, same shaders, same settings: identical 8-bit output.
    EXPECT_EQ(d.maxAbs, 0.0) << "RMSE " << d.rmse;
    // And not an empty image: the background colour (0.2, 0.3, 0.4) is there.
    EXPECT_GT(a.at(2, 80, 2), 0.3f);
}

TEST(ViewTest, NoDisplayIsOneClearError) {
    const CommandResult r =
        runCommand("env -u DISPLAY -u WAYLAND_DISPLAY " + veilExe() + " view '" +
                   (sourceDir() / "datasets/scenes/room.json").string() + "' --frames 1");
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("veil: error:"), std::string::npos) << r.output;
}

} // namespace veil::test
