// `veil view --script actions.json`: the viewer driven by a list of actions instead of the
// mouse, in the real window (Xvfb in tests and CI), one action per displayed frame. The file
// is a JSON array of objects with one action key each:
//   {"set": "volumes.0.density_scale=4"}     an edit, as `veil render --set` takes it (or a
//                                            list of them, applied before one frame)
//   {"oit": "wboit"}, {"shadows": "moment"}  pick a technique (as the panel's combo does)
//   {"camera": "top"}, {"reset_camera": true}
//   {"orbit": [dyaw, dpitch], "zoom": 0.9}   radians; zoom multiplies the distance
//   {"pan": [dx, dy]}                        fractions of the orbit distance
//   {"view": "shadow.depth", "layer": 0}     debug view of a frame resource ("" = the frame)
//   {"open": "scene.json"}                   another scene or .vdb (as the file dialog does)
//   {"resize": [w, h]}, {"reload_shaders": true}, {"frames": N}
//   {"refine_tile_px": 64}                   refine frames in 64 px tiles, one per displayed
//                                            frame (0 = off); the script waits for each
//                                            refined frame before its next action
//   {"refine_budget_ms": 100}                halve a step's tile until its estimated pass
//                                            time fits (0 = whole tiles; scripts default 0)
//   {"screenshot": "out.png"}                the shown image (frame or debug view) at frame
//                                            size; .exr: linear HDR (frame) or the raw values
//                                            of the debug view's resource (its layer)
//   {"window_screenshot": "ui.png"}          the whole window, panel included
//   {"copy_command": "cmd.txt", "output": "out.png"}  the `veil render` line of this view
//   {"save_scene": "edited.json"}
//   {"status": "status.json"}                errors and what renders, as JSON
//   {"expand": ["Volumes", "Lights"]}        open these panel sections, close the others
//   {"frame": 37}                            show frame 37 of an animated scene (pauses);
//                                            the script waits until it is shown or failed
//   {"play": true}, {"step": 1}, {"loop": false}, {"fps": 12}   the timeline: while
//                                            playing, a scripted run advances one frame per
//                                            displayed frame once the last one is shown
//                                            (the play action's frame included)
// The files of open, screenshot, window_screenshot, copy_command, save_scene and status are
// the script's: a relative one is resolved against the script's folder (copy_command's
// "output" is a name in the printed command and stays as written).
// A malformed script is an error naming the file and the action; an action that fails
// (a bad file, a failing technique) is recorded like a click would be and the script goes on.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace veil::viewer {

struct ScriptAction {
    std::string kind; // the action key
    nlohmann::json value;
    nlohmann::json action; // the whole object (extra keys: layer, zoom, output)
    std::size_t index = 0;
};

// Reads and checks the script: throws veil::Error "<file>: action N: ..." for a bad one. The
// actions' relative files come back resolved (resolveAgainstScript).
std::vector<ScriptAction> loadViewScript(const std::filesystem::path& path);

// The actions whose value is a file the viewer reads or writes.
const std::set<std::string>& pathActions();
// `file` of an action of `script`: as written when absolute, else joined to the script's folder
// ("shots/a.png" of "tests/s.json" -> "tests/shots/a.png"; of "s.json" -> "shots/a.png").
std::string resolveAgainstScript(const std::filesystem::path& script, const std::string& file);

} // namespace veil::viewer
