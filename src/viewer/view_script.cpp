#include "viewer/view_script.h"

#include "base/error.h"
#include "base/text.h"
#include "scene/json_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace veil::viewer {

namespace {

// Action key -> the JSON type its value must have.
enum class Want { String, Number, Bool, Array };

Want wantFor(const std::string& kind) {
    static const std::set<std::string> strings = {
        "set",          "oit",        "shadows",    "camera",
        "view",         "open",       "screenshot", "window_screenshot",
        "copy_command", "save_scene", "status"};
    if (strings.count(kind)) return Want::String;
    if (kind == "frames" || kind == "refine_tile_px" || kind == "refine_budget_ms" ||
        kind == "frame" || kind == "step" || kind == "fps")
        return Want::Number;
    if (kind == "reset_camera" || kind == "reload_shaders" || kind == "reuse_shadow_maps" ||
        kind == "play" || kind == "loop")
        return Want::Bool;
    return Want::Array; // orbit, pan, resize, expand
}

bool known(const std::string& kind) {
    static const std::set<std::string> all = {"set",
                                              "oit",
                                              "shadows",
                                              "camera",
                                              "reset_camera",
                                              "orbit",
                                              "pan",
                                              "view",
                                              "open",
                                              "resize",
                                              "reload_shaders",
                                              "frames",
                                              "refine_tile_px",
                                              "refine_budget_ms",
                                              "reuse_shadow_maps",
                                              "screenshot",
                                              "window_screenshot",
                                              "copy_command",
                                              "save_scene",
                                              "status",
                                              "expand",
                                              "frame",
                                              "play",
                                              "step",
                                              "loop",
                                              "fps"};
    return all.count(kind) > 0;
}

} // namespace

const std::set<std::string>& pathActions() {
    static const std::set<std::string> actions = {"open",         "screenshot", "window_screenshot",
                                                  "copy_command", "save_scene", "status"};
    return actions;
}

std::string resolveAgainstScript(const std::filesystem::path& script, const std::string& file) {
    const std::filesystem::path f(file);
    if (f.empty() || f.is_absolute()) return file;
    return (script.parent_path() / f).lexically_normal().string();
}

std::vector<ScriptAction> loadViewScript(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    VEIL_CHECK(in.good() && !std::filesystem::is_directory(path), "cannot open script '{}'",
               path.string());
    std::stringstream text;
    text << in.rdbuf();
    const nlohmann::json doc = scene::parseJsonText(text.str(), path.string());
    VEIL_CHECK(doc.is_array(), "{}: a view script is a JSON array of actions, not a {}",
               path.string(), doc.type_name());
    std::vector<ScriptAction> actions;
    static const std::set<std::string> extras = {"layer", "zoom", "output"};
    for (std::size_t i = 0; i < doc.size(); ++i) {
        const nlohmann::json& a = doc[i];
        const std::string where = fmt::format("{}: action {}", path.string(), i);
        VEIL_CHECK(a.is_object(),
                   "{}: expected an object such as {{\"set\": \"render.exposure=2\"}}", where);
        ScriptAction act;
        act.index = i;
        act.action = a;
        for (const auto& [key, value] : a.items()) {
            if (extras.count(key)) continue;
            VEIL_CHECK(known(key),
                       "{}: unknown action '{}' (known: set, oit, shadows, camera, reset_camera, "
                       "orbit, pan, view, open, resize, reload_shaders, frames, refine_tile_px, "
                       "reuse_shadow_maps, screenshot, "
                       "window_screenshot, copy_command, save_scene, status, expand, frame, "
                       "play, step, loop, fps)",
                       where, printable(key));
            VEIL_CHECK(act.kind.empty(), "{}: two actions ('{}', '{}') in one object", where,
                       act.kind, key);
            act.kind = key;
            act.value = value;
        }
        VEIL_CHECK(!act.kind.empty(), "{}: no action key", where);
        const Want want = wantFor(act.kind);
        // "set" also takes a list of edits, applied before one frame.
        const bool setList = act.kind == "set" && act.value.is_array() &&
                             std::all_of(act.value.begin(), act.value.end(),
                                         [](const nlohmann::json& x) { return x.is_string(); });
        // frames: 1..100000; refine_tile_px: 0 (off)..16384; refine_budget_ms: 0 (off)..1e6.
        // Time: frame and step -1e6..1e6; fps 0.1..1000 (not an integer necessarily).
        const bool tile = act.kind == "refine_tile_px", budget = act.kind == "refine_budget_ms";
        const bool fps = act.kind == "fps", time = act.kind == "frame" || act.kind == "step";
        const double lo = tile || budget ? 0
                          : time         ? -1e6
                          : fps          ? 0.1
                                         : 1,
                     hi = tile             ? 16384
                          : budget || time ? 1e6
                          : fps            ? 1000
                                           : 100000;
        const bool ok = setList || (want == Want::String && act.value.is_string()) ||
                        (want == Want::Number && (act.value.is_number_integer() || budget || fps) &&
                         act.value.is_number() && act.value.get<double>() >= lo &&
                         act.value.get<double>() <= hi) ||
                        (want == Want::Bool && act.value.is_boolean()) ||
                        (want == Want::Array && act.value.is_array());
        VEIL_CHECK(
            ok, "{}: '{}' expects {}, not {}", where, act.kind,
            want == Want::String ? std::string("a string")
            : want == Want::Number
                ? fmt::format("{} in {}..{}", budget || fps ? "a number" : "an integer", lo, hi)
            : want == Want::Bool ? std::string("true or false")
                                 : std::string("an array"),
            scene::describeJson(act.value));
        if (act.kind == "orbit" || act.kind == "pan" || act.kind == "resize") {
            VEIL_CHECK(act.value.size() == 2 && act.value[0].is_number() &&
                           act.value[1].is_number(),
                       "{}: '{}' expects two numbers", where, act.kind);
            // Radians (orbit) or view-plane steps in units of the distance (pan): beyond 1e6
            // they mean nothing, and doubles past FLT_MAX would become inf.
            for (const auto& v : act.value)
                VEIL_CHECK(std::abs(v.get<double>()) <= 1e6,
                           "{}: '{}' expects two numbers in -1e6..1e6, not {}", where, act.kind,
                           scene::describeJson(v));
            if (act.kind == "resize")
                for (const auto& v : act.value)
                    VEIL_CHECK(v.is_number_integer() && v.get<long long>() >= 1 &&
                                   v.get<long long>() <= 16384,
                               "{}: 'resize' expects two integers in 1..16384", where);
        }
        if (act.kind == "expand")
            for (const auto& v : act.value)
                VEIL_CHECK(v.is_string(), "{}: 'expand' expects section names", where);
        if (a.contains("layer"))
            VEIL_CHECK(a["layer"].is_number_integer() && a["layer"].get<long long>() >= 0,
                       "{}: 'layer' must be an integer >= 0", where);
        if (a.contains("zoom"))
            VEIL_CHECK(a["zoom"].is_number() && a["zoom"].get<double>() >= 1e-6 &&
                           a["zoom"].get<double>() <= 1e6,
                       "{}: 'zoom' must be a number in 1e-6..1e6 (a distance factor)", where);
        if (a.contains("output"))
            VEIL_CHECK(a["output"].is_string(), "{}: 'output' must be a string", where);
        // A relative file of an action is the script's: resolved against its folder, not the
        // working directory (so a script beside its outputs runs from anywhere).
        if (pathActions().count(act.kind) && act.value.is_string())
            act.value = resolveAgainstScript(path, act.value.get<std::string>());
        // No output may replace the script being run (save_scene, screenshots, ...).
        static const std::set<std::string> writers = {"screenshot", "window_screenshot",
                                                      "copy_command", "save_scene", "status"};
        const std::array<const nlohmann::json*, 2> outputs = {
            &act.value, a.contains("output") ? &a["output"] : nullptr};
        for (const nlohmann::json* out : outputs) {
            if (!out || !out->is_string() || !writers.count(act.kind)) continue;
            std::error_code ec;
            VEIL_CHECK(!std::filesystem::equivalent(path, out->get<std::string>(), ec),
                       "{}: '{}' would overwrite the script '{}' itself", where, act.kind,
                       path.string());
        }
        actions.push_back(std::move(act));
    }
    return actions;
}

} // namespace veil::viewer
