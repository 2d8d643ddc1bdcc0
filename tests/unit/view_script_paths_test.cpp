// `veil view --script`: an action's relative file is the script's, resolved against the
// script's folder and not the working directory (a script run from the clone's root wrote its
// screenshots there); absolute files and copy_command's "output" stay as written.
#include "base/error.h"
#include "support/test_support.h"
#include "viewer/view_script.h"

#include <gtest/gtest.h>

namespace veil::test {

namespace fs = std::filesystem;

TEST(ViewScriptPathsTest, RelativeFilesResolveAgainstTheScriptsFolder) {
    const fs::path d = freshOutputDir("view_script_paths", "scripts");
    const fs::path script = writeTextFile(d / "tune.json", R"([
      {"window_screenshot": "panel.png"}, {"screenshot": "shots/frame.png"},
      {"copy_command": "command.json", "output": "frame-render.png"},
      {"status": "../status.json"}, {"save_scene": "/tmp/edited.json"},
      {"open": "scene.json"}, {"oit": "wboit"}])");
    const std::vector<viewer::ScriptAction> a = viewer::loadViewScript(script);
    ASSERT_EQ(a.size(), 7u);
    EXPECT_EQ(a[0].value, (d / "panel.png").string());
    EXPECT_EQ(a[1].value, (d / "shots/frame.png").string());
    EXPECT_EQ(a[2].value, (d / "command.json").string());
    EXPECT_EQ(a[2].action["output"], "frame-render.png"); // a name in the printed command
    EXPECT_EQ(a[3].value, (d.parent_path() / "status.json").string());
    EXPECT_EQ(a[4].value, "/tmp/edited.json");
    EXPECT_EQ(a[5].value, (d / "scene.json").string());
    EXPECT_EQ(a[6].value, "wboit"); // not a file
    // A script given by a bare name (run from its folder) keeps its files relative.
    EXPECT_EQ(viewer::resolveAgainstScript("tune.json", "panel.png"), "panel.png");
}

// The script's own file is recognised through its folder: saving over it is refused even
// when the script is run from elsewhere.
TEST(ViewScriptPathsTest, OverwritingTheScriptIsRefusedFromAnyFolder) {
    const fs::path d = freshOutputDir("view_script_paths", "self");
    const fs::path script = writeTextFile(d / "s.json", R"([{"save_scene": "s.json"}])");
    try {
        viewer::loadViewScript(script);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("would overwrite the script"), std::string::npos)
            << e.what();
    }
}

} // namespace veil::test
