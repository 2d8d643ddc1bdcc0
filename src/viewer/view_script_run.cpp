// A view script run in the viewer's loop (view_script_run.h).
#include "viewer/view_script_run.h"

#include "viewer/screenshot.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "fog/fog_pass.h"

#include <fmt/format.h>

#include <iostream>

namespace veil::viewer {

namespace {

bool isOutput(const std::string& kind) {
    return kind == "screenshot" || kind == "window_screenshot" || kind == "copy_command" ||
           kind == "save_scene" || kind == "status";
}

// The timeline's actions (frame, play, step, loop, fps); false for any other.
bool applyTimeAction(const ScriptAction& a, session::TimelinePlayer& t) {
    if (a.kind == "frame") {
        t.play(false);
        t.seek(a.value.get<int>());
    } else if (a.kind == "play") {
        t.play(a.value.get<bool>());
    } else if (a.kind == "step") {
        t.play(false);
        t.step(a.value.get<int>());
    } else if (a.kind == "loop") {
        t.setLoop(a.value.get<bool>());
    } else if (a.kind == "fps") {
        t.setFps(a.value.get<double>());
    } else {
        return false;
    }
    return true;
}

// Applies a state-changing action; returns the frames it asks to wait (frames action).
int applyAction(const ScriptAction& a, const ScriptTarget& t) {
    session::ViewSession& s = t.session;
    const nlohmann::json& v = a.value;
    if (a.kind == "set" && v.is_array())
        for (const auto& kv : v)
            s.set(kv.get<std::string>());
    else if (a.kind == "set")
        s.set(v.get<std::string>());
    else if (a.kind == "oit")
        s.selectOit(v.get<std::string>());
    else if (a.kind == "shadows")
        s.selectShadows(v.get<std::string>());
    else if (a.kind == "camera")
        s.selectCamera(v.get<std::string>());
    else if (a.kind == "reset_camera")
        s.resetCamera();
    else if (a.kind == "orbit")
        s.orbitBy(v[0].get<float>(), v[1].get<float>(),
                  a.action.contains("zoom") ? a.action["zoom"].get<float>() : 1.0f);
    else if (a.kind == "pan")
        s.panBy(v[0].get<float>(), v[1].get<float>());
    else if (a.kind == "view") {
        const std::string name = v.get<std::string>();
        t.view.select(name == "frame" ? "" : name,
                      a.action.contains("layer") ? a.action["layer"].get<int>() : 0);
    } else if (a.kind == "open")
        s.open(v.get<std::string>());
    else if (a.kind == "resize")
        s.resize(v[0].get<int>(), v[1].get<int>());
    else if (a.kind == "reload_shaders")
        s.reloadShaders();
    else if (a.kind == "expand") {
        t.expand.clear();
        for (const auto& name : v)
            t.expand.insert(name.get<std::string>());
    } else if (a.kind == "refine_tile_px")
        s.setRefineTilePx(v.get<int>());
    else if (a.kind == "refine_budget_ms")
        s.setRefineBudgetMs(v.get<double>());
    else if (a.kind == "reuse_shadow_maps")
        s.setReuseShadowMaps(v.get<bool>());
    else if (a.kind == "frames")
        return v.get<int>();
    return 1;
}

// What the status action writes: errors and what renders.
nlohmann::json statusJson(const session::ViewSession& session, const DebugView& view) {
    const frame::Renderer& r = session.renderer();
    nlohmann::json j = {{"errors", session.errors()},
                        {"last_error", session.lastError()},
                        {"frame_failed", session.frameFailed()},
                        {"scene", session.scenePath().string()},
                        {"camera", session.cameraName()},
                        {"oit", r.oitName()},
                        {"oit_stats", r.technique().stats()},
                        {"shadows", r.shadowTechnique().name()},
                        {"debug_view", view.resource()},
                        {"debug_range", {view.lo(), view.hi()}},
                        {"width", r.width()},
                        {"height", r.height()},
                        {"overrides", session.overrides()},
                        {"frames_replaced", session.framesReplaced()},
                        {"renderer", session.context().renderer}};
    // Volume uploads from host memory, and timeline frames shown again from the frames held on
    // the GPU without one (render.sequence_gpu_cache_mib, fog/gpu_volume.h).
    std::size_t uploads = 0, reshown = 0;
    if (const volume::FogPass* fog = r.fog())
        for (const volume::GpuVolumeStats& v : fog->stats()) {
            uploads += v.uploads;
            reshown += v.reshown;
        }
    j["volume_uploads"] = uploads;
    j["volume_frames_reshown"] = reshown;
    const session::ViewSession::RefineLog& log = session.refineLog();
    j["refinement"] = {{"tile_px", session.refineTilePx()},
                       {"tiles", log.tiles},
                       {"budget_ms", session.refineBudgetMs()},
                       {"steps", log.steps},
                       {"min_tile_px", log.minTilePx},
                       {"ui_frames", log.uiFrames},
                       {"max_tiles_per_ui_frame", log.maxTilesPerUiFrame},
                       {"light_slabs", log.lightSlabs},
                       {"max_light_slabs_per_ui_frame", log.maxLightSlabsPerUiFrame},
                       {"shadow_steps", log.shadowSteps},
                       {"max_per_frame_steps_per_ui_frame", log.maxPerFrameStepsPerUiFrame},
                       {"max_pixels_per_ui_frame", log.maxPixelsPerUiFrame},
                       {"margin_px", r.refineMarginPx()},
                       {"first_ui_frame_ms", log.firstUiFrameMs},
                       {"max_tile_ui_frame_ms", log.maxTileUiFrameMs},
                       {"max_ui_frame_ms", log.maxUiFrameMs},
                       {"total_ms", log.totalMs},
                       {"complete", log.complete},
                       {"completed", log.completed},
                       {"refining", session.refining()}};
    j["shadow_maps"] = {{"reuse", r.reusesShadowMaps()},
                        {"depends_on_camera", r.shadowTechnique().dependsOnCamera()},
                        {"renders", r.shadowMapRenders()},
                        {"reuses", r.shadowMapReuses()}};
    if (view.errorView() && view.error())
        j["error_vs_reference"] = {{"rmse", view.error()->error().rmse},
                                   {"max_abs", view.error()->maxAbs()}};
    return j;
}

} // namespace

ScriptRunner::ScriptRunner(std::vector<ScriptAction> actions, std::string path)
    : actions_(std::move(actions)), path_(std::move(path)) {}

bool ScriptRunner::beforeFrame(const ScriptTarget& t) {
    this_ = nullptr;
    if (t.session.refining()) return false; // the next action sees the whole frame
    if (t.timeline.pending()) return false; // ... and the timeline's frame shown (or failed)
    if (wait_ > 0) {
        --wait_;
        return true;
    }
    if (next_ >= actions_.size()) return false;
    this_ = &actions_[next_++];
    // frame, play and step on a scene without a timeline would do nothing: said, not ignored.
    const std::string& kind = this_->kind;
    const bool moves = kind == "step" || (kind == "play" && this_->value.get<bool>()) ||
                       (kind == "frame" && this_->value.get<int>() != t.timeline.range().first);
    if (moves && !t.timeline.animated())
        throw Error(fmt::format("{}: action {} ({}): the scene has no timeline (no file "
                                "sequence, camera or light keys, turntable or time.frame_range "
                                "of more than one frame) to {}",
                                path_, this_->index, kind, kind == "play" ? "play" : "move along"));
    if (applyTimeAction(*this_, t.timeline))
        wait_ = 0;
    else if (!isOutput(this_->kind))
        wait_ = applyAction(*this_, t) - 1;
    else if (this_->kind == "save_scene")
        t.session.saveSceneAs(this_->value.get<std::string>());
    return false;
}

void ScriptRunner::afterFrame(const session::ViewSession& session, const DebugView& view, int width,
                              int height) {
    if (!this_ || !isOutput(this_->kind) || this_->kind == "save_scene") return;
    const ScriptAction& a = *this_;
    const std::string path = a.value.get<std::string>();
    const std::string what = fmt::format("{}: action {} ({})", path_, a.index, a.kind);
    checkOutputPath(path, what.c_str(), {path_, session.scenePath()});
    if (a.kind == "screenshot") {
        const std::string ext = lowerExtension(path);
        VEIL_CHECK(ext == ".png" || ext == ".exr", "{}: '{}' must end in .png or .exr", what, path);
        writeShownImage(session, view, path);
    } else if (a.kind == "window_screenshot") {
        writeWindowImage(path, width, height);
    } else if (a.kind == "copy_command") {
        const std::string output =
            a.action.contains("output") ? a.action["output"].get<std::string>() : "out.png";
        const nlohmann::json j = {{"line", session.renderCommand(output)},
                                  {"arguments", session.renderArguments(output)}};
        writeTextFileAtomically(path, j.dump(2) + "\n");
    } else if (a.kind == "status") {
        writeTextFileAtomically(path, statusJson(session, view).dump(2) + "\n");
    }
    std::cout << "wrote " << path << "\n";
}

bool ScriptRunner::finished(const session::ViewSession& session) const {
    return !path_.empty() && next_ >= actions_.size() && wait_ == 0 && !session.refining();
}

} // namespace veil::viewer
