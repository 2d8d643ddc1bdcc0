// The viewer's ImGui panel over a session::ViewSession: techniques (unavailable ones greyed with
// the reason; the combo shows what renders), every declared property of the OIT and shadow
// techniques as generated widgets (property_widgets.h), the fog marcher, each volume,
// light and the camera, the render settings, debug views of every frame resource, frame
// times, per-pass times, GPU memory per resource, errors, and the file actions (open, save
// scene as, copy render command, PNG + EXR screenshot into a folder: viewer/screenshot.h).
// Every edit goes through session::ViewSession::set as the `--set` override it is.
#pragma once

#include "viewer/debug_view.h"
#include "viewer/session/view_session.h"
#include "viewer/ui/file_dialog.h"

#include <deque>
#include <set>
#include <string>
#include <vector>

struct GLFWwindow;

namespace veil::ui {

struct PanelState {
    std::set<std::string> expand; // a script's {"expand": [...]}: open these, close the rest
    FileDialog openDialog{"Open scene or .vdb", {".json", ".vdb"}};
    std::string saveAs = "edited-scene.json";
    std::string screenshotFolder = ".";
    std::string copiedCommand;
    std::deque<float> frameMs; // the last frames' total pass times
    int screenshotCount = 0;
};

// The keys of a volume's widgets that mean nothing for `volume` and are not shown: its
// temperature_scale, temperature_offset and temperature_intensity without a temperature grid.
std::vector<std::string> hiddenVolumeKeys(const scene::VolumeRef& volume);

// Draws the panel; edits act on `session` and `view` at once.
void drawPanel(GLFWwindow* window, session::ViewSession& session, viewer::DebugView& view,
               PanelState& state);

} // namespace veil::ui
