// `veil view`'s window (GLFW + Dear ImGui): the session's frame fitted into the window, the
// panel (view_panel.h) and the timeline (timeline_panel.h) over it, the mouse orbiting and
// panning the camera, files dropped on the window opened. Interactive frames render at a
// quarter of the size while the camera moves when full frames are slow, and full-size frames
// refine in tiles (session::ViewSession::setRefineTilePx). Scripted runs, a --script
// (viewer/view_script_run.h) or --frames N, render at the frame size exactly and exit.
#pragma once

#include <string>
#include <vector>

namespace veil::ui {

struct ViewerOptions {
    std::string scene; // a scene .json or a bare .vdb
    std::string camera, oit, shadows;
    std::string screenshot;                // with frames: the last frame's image
    std::string script;                    // a view script (viewer/view_script.h)
    int width = 0, height = 0;             // the frame (default: the scene's; interactive:
                                           // the window's)
    int windowWidth = 0, windowHeight = 0; // default: the frame's when scripted, else at
                                           // least 1280 x 720
    int frames = 0;                        // 0 = interactive (or the script's)
    int refineTilePx = -1;              // view.refine_tile_px; -1 = the default (128 on a software
                                        // renderer when interactive, else 0 = off)
    double refineBudgetMs = -1.0;       // view.refine_budget_ms; -1 = the default (100 interactive)
    bool reuseShadowMaps = true;        // view.reuse_shadow_maps
    std::vector<std::string> overrides; // --set key=value
};

// Opens the window and runs until it is closed, the script is done or `frames` frames are
// shown. Throws veil::Error when the script or the first scene cannot be read, or a technique
// chosen in the options does not start; later errors are shown in the panel.
void runViewer(const ViewerOptions& options);

} // namespace veil::ui
