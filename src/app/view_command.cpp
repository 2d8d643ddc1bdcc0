// `veil view <scene.json|file.vdb>`: explore a scene in a window. The arguments are checked
// here; the window, its panel and the scripted runs are the viewer's (viewer/ui/view_window.h).
#include "app/cli_checks.h"
#include "app/commands.h"

#include "viewer/ui/view_window.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"

#include <memory>

namespace veil::app {

namespace {

void runView(const ui::ViewerOptions& args) {
    if (!args.screenshot.empty()) {
        VEIL_CHECK(args.frames > 0, "--screenshot needs --frames (or use a --script)");
        const std::string ext = lowerExtension(args.screenshot);
        VEIL_CHECK(ext == ".png" || ext == ".exr", "--screenshot '{}' must end in .png or .exr",
                   args.screenshot);
        checkOutputPath(args.screenshot, "--screenshot", {args.scene});
    }
    VEIL_CHECK(args.script.empty() || args.frames == 0, "--script and --frames exclude each other");
    ui::runViewer(args);
}

} // namespace

void addViewCommand(CLI::App& app) {
    auto args = std::make_shared<ui::ViewerOptions>();
    CLI::App* cmd = app.add_subcommand("view", "Explore a scene in a window (needs a display)");
    cmd->add_option("scene", args->scene, "Scene file (JSON) or an OpenVDB file (.vdb)")
        ->required();
    cmd->add_option("--width", args->width,
                    "Frame width (default: the scene's; interactive: the "
                    "window's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--height", args->height, "Frame height (as --width)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--window-width", args->windowWidth,
                    "Window width (default: 1280 or the frame's; scripted: the frame's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--window-height", args->windowHeight, "Window height (as --window-width)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--camera", args->camera, "Camera name");
    cmd->add_option("--oit", args->oit, "Transparency technique");
    cmd->add_option("--shadows", args->shadows, "Shadow technique");
    cmd->add_option("--set", args->overrides, "Override a scene value: key=value");
    cmd->add_option("--script", args->script,
                    "Run the actions of this JSON file in the window, then exit (docs/viewer.md)");
    cmd->add_option("--refine-tile-px", args->refineTilePx,
                    "view.refine_tile_px: refine full-size frames in tiles of this many pixels, "
                    "one per UI frame (0 = off; default: 128 on a software renderer, "
                    "interactive only)")
        ->check(CLI::Range(0, 16384));
    cmd->add_option("--refine-budget-ms", args->refineBudgetMs,
                    "view.refine_budget_ms: halve a refinement step's tile until its estimated "
                    "pass time is under this many ms (down to 16 px; 0 = whole tiles; default: "
                    "100 interactive, 0 scripted)")
        ->check(finiteRange(0.0, 1e6));
    cmd->add_option("--reuse-shadow-maps", args->reuseShadowMaps,
                    "view.reuse_shadow_maps: keep the shadow maps across frames while nothing they "
                    "depend on changed (camera moves keep them; techniques whose maps follow the "
                    "camera, e.g. volume, redraw; default true)");
    cmd->add_option("--frames", args->frames,
                    "Render this many frames without the GUI, then exit (for tests)")
        ->check(CLI::Range(1, 100000));
    cmd->add_option("--screenshot", args->screenshot,
                    "With --frames: save the last frame (.png; .exr = linear HDR)");
    // What the viewer window reads from the mouse and keyboard (viewer/ui/view_window.cpp);
    // kept here so --help tells the truth.
    cmd->footer("Key bindings:\n"
                "  left drag          orbit the camera around its target\n"
                "  right/middle drag  pan\n"
                "  wheel              zoom (orbit distance)\n"
                "  R                  reload shaders from disk (failing programs keep the last "
                "good)\n"
                "  drop a file        open a scene (.json) or .vdb\n"
                "  window close       quit\n"
                "The panel (docs/viewer.md) edits every technique property, the fog, volumes, "
                "lights and camera, shows debug views of every frame resource, frame and pass "
                "times, and copies the `veil render` command of the view. The layout is kept "
                "in $XDG_CONFIG_HOME/veil/imgui.ini.");
    cmd->callback([args] { runView(*args); });
}

} // namespace veil::app
