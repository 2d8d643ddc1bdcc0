// `veil view <scene.json|file.vdb>`: explore a scene in a window (GLFW + Dear ImGui). The
// state is a session::ViewSession (session/view_session.h), the panel app/view_panel.h, debug views
// viewer/debug_view.h. `--script actions.json` drives the same window from a list of actions
// (viewer/view_script.h); `--frames N --screenshot out.png` renders N frames without the panel.
#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/timeline_panel.h"
#include "app/view_panel.h"
#include "session/view_session.h"
#include "viewer/debug_view.h"
#include "viewer/view_script.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/log.h"
#include "base/text.h"
#include "gpu/readback.h"
#include "gpu/window_context.h"
#include "io/image_io.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>

namespace veil::app {

namespace fs = std::filesystem;

namespace {

struct ViewArgs {
    std::string scene;
    std::string camera;
    std::string oit;
    std::string shadows;
    std::string screenshot;
    std::string script;
    int width = 0, height = 0;
    int windowWidth = 0, windowHeight = 0; // scripted: the window (default: the frame size)
    int frames = 0;                        // 0 = interactive
    int refineTilePx = -1;        // view.refine_tile_px; -1 = the default (128 on a software
                                  // renderer when interactive, else 0 = off)
    double refineBudgetMs = -1.0; // view.refine_budget_ms; -1 = the default (100 interactive)
    bool reuseShadowMaps = true;  // view.reuse_shadow_maps
    std::vector<std::string> overrides;
};

// $XDG_CONFIG_HOME/veil (else ~/.config/veil), created; empty when neither is known.
fs::path configDirectory() {
    fs::path base;
    if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x)
        base = x;
    else if (const char* h = std::getenv("HOME"); h && *h)
        base = fs::path(h) / ".config";
    if (base.empty()) return {};
    std::error_code ec;
    fs::create_directories(base / "veil", ec);
    return ec ? fs::path() : base / "veil";
}

class ImGuiSession {
public:
    ImGuiSession(GLFWwindow* window, bool keepLayout) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        // The layout (the panel's size and place, open sections) is kept between runs in
        // imgui.ini, loaded here and written whole and atomically when ImGui asks (saveLayout),
        // so a crash never leaves half a file. Scripted runs ignore it (same image every time).
        io.IniFilename = nullptr;
        if (keepLayout)
            if (const fs::path dir = configDirectory(); !dir.empty()) {
                ini_ = dir / "imgui.ini";
                if (fs::is_regular_file(ini_)) ImGui::LoadIniSettingsFromDisk(ini_.c_str());
            }
        // High-DPI: the monitor's content scale sizes the font and the widgets.
        float sx = 1.0f, sy = 1.0f;
        glfwGetWindowContentScale(window, &sx, &sy);
        const float scale = std::clamp(std::max(sx, sy), 1.0f, 4.0f);
        ImGui::GetStyle().ScaleAllSizes(scale);
        io.FontGlobalScale = scale;
        ImGui_ImplGlfw_InitForOpenGL(window, true);
        ImGui_ImplOpenGL3_Init("#version 450 core");
    }
    ~ImGuiSession() {
        saveLayout(true);
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiSession(const ImGuiSession&) = delete;
    ImGuiSession& operator=(const ImGuiSession&) = delete;

    // Writes imgui.ini when the layout changed (ImGui sets WantSaveIniSettings a few seconds
    // after a change) and, `always`, at the end; a write that fails is logged.
    void saveLayout(bool always = false) {
        ImGuiIO& io = ImGui::GetIO();
        if (ini_.empty() || !(always || io.WantSaveIniSettings)) return;
        io.WantSaveIniSettings = false;
        try {
            writeTextFileAtomically(ini_, ImGui::SaveIniSettingsToMemory());
        } catch (const std::exception& e) {
            log::warn("cannot keep the panel layout: {}", e.what());
        }
    }

private:
    fs::path ini_;
};

// Files dropped on the window (GLFW calls back without a user pointer of ours).
std::vector<std::string>& droppedFiles() {
    static std::vector<std::string> files;
    return files;
}
void onDrop(GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i)
        droppedFiles().emplace_back(paths[i]);
}

// The first scene's frame size (its render.width/height) for the window.
void sceneSize(const ViewArgs& args, int& w, int& h) {
    w = args.width;
    h = args.height;
    if (w > 0 && h > 0) return;
    int sw = 640, sh = 360;
    if (lowerExtension(args.scene) != ".vdb") {
        const scene::Scene s = scene::loadScene(args.scene, args.overrides);
        sw = s.render.width;
        sh = s.render.height;
    } else {
        sw = sh = 512;
    }
    if (w <= 0) w = sw;
    if (h <= 0) h = sh;
}

// Writes what an output action asks for, after the frame of its iteration.
void scriptOutput(const viewer::ScriptAction& a, session::ViewSession& session,
                  const viewer::DebugView& view, const std::string& scriptPath) {
    const std::string path = a.value.get<std::string>();
    const std::string what = fmt::format("{}: action {} ({})", scriptPath, a.index, a.kind);
    checkOutputPath(path, what.c_str(), {scriptPath, session.scenePath()});
    if (a.kind == "screenshot") {
        const std::string ext = lowerExtension(path);
        VEIL_CHECK(ext == ".png" || ext == ".exr", "{}: '{}' must end in .png or .exr", what, path);
        writeShownImage(session, view, path);
    } else if (a.kind == "window_screenshot") {
        int w = 0, h = 0;
        glfwGetFramebufferSize(glfwGetCurrentContext(), &w, &h);
        ImageF img(w, h, 4);
        std::vector<float> rows(img.pixels.size());
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, rows.data());
        const std::size_t row = std::size_t(w) * 4;
        for (int y = 0; y < h; ++y)
            std::copy_n(rows.begin() + (h - 1 - y) * row, row, img.pixels.begin() + y * row);
        for (std::size_t i = 3; i < img.pixels.size(); i += 4)
            img.pixels[i] = 1.0f;
        io::writeImage(path, img);
    } else if (a.kind == "copy_command") {
        const std::string output =
            a.action.contains("output") ? a.action["output"].get<std::string>() : "out.png";
        nlohmann::json j = {{"line", session.renderCommand(output)},
                            {"arguments", session.renderArguments(output)}};
        writeTextFileAtomically(path, j.dump(2) + "\n");
    } else if (a.kind == "status") {
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
                            {"renderer", session.context().renderer}};
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
        writeTextFileAtomically(path, j.dump(2) + "\n");
    }
    std::cout << "wrote " << path << "\n";
}

// Applies a state-changing action; returns the frames it asks to wait (frames action).
int scriptApply(const viewer::ScriptAction& a, session::ViewSession& s, viewer::DebugView& view,
                PanelState& panel) {
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
        view.select(name == "frame" ? "" : name,
                    a.action.contains("layer") ? a.action["layer"].get<int>() : 0);
    } else if (a.kind == "open")
        s.open(v.get<std::string>());
    else if (a.kind == "resize")
        s.resize(v[0].get<int>(), v[1].get<int>());
    else if (a.kind == "reload_shaders")
        s.reloadShaders();
    else if (a.kind == "expand") {
        panel.expand.clear();
        for (const auto& name : v)
            panel.expand.insert(name.get<std::string>());
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

// The timeline's actions (frame, play, step, loop, fps); false for any other.
bool applyTimeAction(const viewer::ScriptAction& a, session::TimelinePlayer& t) {
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

bool isOutput(const std::string& kind) {
    return kind == "screenshot" || kind == "window_screenshot" || kind == "copy_command" ||
           kind == "save_scene" || kind == "status";
}

void runView(const ViewArgs& args) {
    if (!args.screenshot.empty()) {
        VEIL_CHECK(args.frames > 0, "--screenshot needs --frames (or use a --script)");
        const std::string ext = lowerExtension(args.screenshot);
        VEIL_CHECK(ext == ".png" || ext == ".exr", "--screenshot '{}' must end in .png or .exr",
                   args.screenshot);
        checkOutputPath(args.screenshot, "--screenshot", {args.scene});
    }
    VEIL_CHECK(args.script.empty() || args.frames == 0, "--script and --frames exclude each other");
    std::vector<viewer::ScriptAction> script;
    if (!args.script.empty()) script = viewer::loadViewScript(args.script);
    const bool scripted = args.frames > 0 || !args.script.empty();

    int width = 0, height = 0;
    sceneSize(args, width, height);
    // Interactive: room for the panel beside a small scene; scripted: the frame size exactly.
    const int ww = args.windowWidth > 0 ? args.windowWidth
                   : scripted           ? width
                                        : std::max(width, 1280);
    const int wh = args.windowHeight > 0 ? args.windowHeight
                   : scripted            ? height
                                         : std::max(height, 720);
    gpu::WindowContext window(ww, wh, "veil view: " + args.scene);
    int fw = 0, fh = 0;
    window.framebufferSize(fw, fh);
    session::ViewSession session(window.info(), args.scene, args.overrides, args.camera,
                                 scripted ? width : fw, scripted ? height : fh);
    // Command-line choices are part of the start: a bad one is the command's error.
    if (!args.oit.empty() && !session.selectOit(args.oit)) throw Error(session.lastError());
    if (!args.shadows.empty() && !session.selectShadows(args.shadows))
        throw Error(session.lastError());
    session.setReuseShadowMaps(args.reuseShadowMaps);
    session.setRefineTilePx(args.refineTilePx >= 0                        ? args.refineTilePx
                            : !scripted && window.info().softwareRenderer ? 128
                                                                          : 0);
    session.setRefineBudgetMs(args.refineBudgetMs >= 0.0 ? args.refineBudgetMs
                              : scripted                 ? 0.0
                                                         : 100.0);

    // The timeline of an animated scene (made again when another scene is opened).
    auto timeline = std::make_unique<session::TimelinePlayer>(session);
    std::filesystem::path timelineScene = session.scenePath();
    auto lastTick = std::chrono::steady_clock::now();

    std::unique_ptr<ImGuiSession> gui;
    if (args.frames == 0) gui = std::make_unique<ImGuiSession>(window.window(), !scripted);
    glfwSetDropCallback(window.window(), onDrop);

    viewer::DebugView view;
    PanelState panel;
    std::uint64_t renderedVersion = ~std::uint64_t(0);
    std::string renderedView = "\x01";
    int renderedLayer = -1;
    std::string shownView; // the debug view the last update showed
    std::size_t next = 0;  // script action
    int wait = 0;          // frames left of a "frames" action
    int frame = 0;
    bool preview = false; // reduced resolution while the camera moves
    auto lastMove = std::chrono::steady_clock::now();
    double lastFullMs = 0.0;
    auto refineStart = std::chrono::steady_clock::now();
    double refineMs = 0.0;    // pass times of the refinement in progress
    bool lastRefined = false; // the frame's resources are from a refinement
    while (!window.shouldClose()) {
        window.pollEvents();
        window.framebufferSize(fw, fh);
        const viewer::ScriptAction* action = nullptr;
        bool force = false;
        if (session.refining()) {
            // The script waits for the refined frame (its next action sees the whole frame).
        } else if (scripted && timeline->pending()) {
            // ... and for the timeline's frame to be shown (or to fail).
        } else if (wait > 0) {
            --wait;
            force = true;
        } else if (next < script.size()) {
            action = &script[next++];
            if (applyTimeAction(*action, *timeline))
                wait = 0;
            else if (!isOutput(action->kind))
                wait = scriptApply(*action, session, view, panel) - 1;
            else if (action->kind == "save_scene")
                session.saveSceneAs(action->value.get<std::string>());
        }
        if (gui) {
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            ImGuiIO& io = ImGui::GetIO();
            bool moving = false;
            if (!scripted && !io.WantCaptureMouse) {
                if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
                    session.orbitBy(-io.MouseDelta.x * 0.01f, io.MouseDelta.y * 0.01f, 1.0f);
                    moving = true;
                }
                if (ImGui::IsMouseDragging(ImGuiMouseButton_Right) ||
                    ImGui::IsMouseDragging(ImGuiMouseButton_Middle)) {
                    session.panBy(-io.MouseDelta.x * 0.002f, io.MouseDelta.y * 0.002f);
                    moving = true;
                }
                if (io.MouseWheel != 0.0f) {
                    session.orbitBy(0.0f, 0.0f, std::pow(0.9f, io.MouseWheel));
                    moving = true;
                }
            }
            if (!scripted && !io.WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_R))
                session.reloadShaders();
            // Progressive: slow frames (llvmpipe fog) render at 1/4 size while the camera
            // moves and at full size once it has rested for 0.3 s.
            const auto now = std::chrono::steady_clock::now();
            if (moving) lastMove = now;
            const bool resting = now - lastMove > std::chrono::milliseconds(300);
            if (!scripted && fw > 0 && fh > 0) {
                if (moving && lastFullMs > 50.0 && !preview) {
                    preview = session.resize(std::max(1, fw / 4), std::max(1, fh / 4));
                } else if (preview && resting) {
                    preview = false;
                    session.resize(fw, fh);
                } else if (!preview) {
                    session.resize(fw, fh);
                }
            }
            drawPanel(window.window(), session, view, panel);
            drawTimeline(*timeline);
            for (const std::string& f : droppedFiles())
                session.open(f);
            droppedFiles().clear();
        }
        if (session.scenePath() != timelineScene) {
            timeline = std::make_unique<session::TimelinePlayer>(session);
            timelineScene = session.scenePath();
        }
        {
            const auto now = std::chrono::steady_clock::now();
            timeline->update(session, std::chrono::duration<double>(now - lastTick).count(),
                             scripted);
            lastTick = now;
        }
        // A frame in one piece, or a refinement begun (the frame's per-frame passes) and then
        // one tile per UI frame (camera input or an edit changes the version: it starts again).
        // A debug view shows the frame's resources, which a refinement leaves holding the last
        // tile's work (the OIT targets): under a debug view the frame renders in one piece.
        bool ran = false, completed = false;
        if (force || session.version() != renderedVersion || (view.active() && lastRefined)) {
            refineStart = std::chrono::steady_clock::now();
            refineMs = 0.0;
            completed = session.renderFrame(!preview && !view.active());
            lastRefined = session.refining();
            ran = true;
            renderedVersion = session.version();
        } else if (session.refining()) {
            completed = session.refineStep();
            ran = true;
        }
        if (ran)
            for (const auto& p : session.renderer().passTimes())
                refineMs += p.milliseconds;
        if (completed) {
            panel.frameMs.push_back(static_cast<float>(refineMs));
            if (panel.frameMs.size() > 240) panel.frameMs.pop_front();
            if (!preview) // the whole frame's wall time, over all of its UI frames
                lastFullMs = std::chrono::duration<double, std::milli>(
                                 std::chrono::steady_clock::now() - refineStart)
                                 .count();
            renderedView = "\x01"; // the debug view reads the new frame
        }
        session.endUiFrame();
        if (view.resource() != renderedView || view.layer() != renderedLayer) {
            // The shown view was another technique's target (the technique was switched):
            // back to the frame. (A view chosen now that does not exist is an error below.)
            if (view.active() && !view.errorView() && view.resource() == shownView) {
                const std::vector<std::string> all = session.renderer().passes().resources();
                if (std::find(all.begin(), all.end(), view.resource()) == all.end()) {
                    session.setStatus("debug view '" + view.resource() +
                                      "' is not a resource of this frame: showing the frame");
                    view.select("");
                }
            }
            try {
                view.update(session);
            } catch (const Error& e) {
                session.fail(e.what());
                view.select("");
            }
            renderedView = view.resource();
            renderedLayer = view.layer();
            shownView = view.resource();
        }
        // The shown image, fitted into the window with its aspect.
        const gpu::Texture& shown = view.active() ? view.texture() : session.displayTexture();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fw, fh);
        const float bg[4] = {0.08f, 0.08f, 0.09f, 1.0f};
        glClearNamedFramebufferfv(0, GL_COLOR, 0, bg);
        if (shown) {
            gpu::Framebuffer source;
            source.attach(GL_COLOR_ATTACHMENT0, shown);
            const double s = std::min(double(fw) / shown.width(), double(fh) / shown.height());
            const int w = int(std::lround(shown.width() * s)),
                      h = int(std::lround(shown.height() * s));
            const int x0 = (fw - w) / 2, y0 = (fh - h) / 2;
            glBlitNamedFramebuffer(source.id(), 0, 0, 0, shown.width(), shown.height(), x0, y0,
                                   x0 + w, y0 + h, GL_COLOR_BUFFER_BIT,
                                   view.active() || s == 1.0 ? GL_NEAREST : GL_LINEAR);
        }
        if (gui) {
            ImGui::Render();
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            gui->saveLayout();
        }
        if (action && isOutput(action->kind) && action->kind != "save_scene")
            scriptOutput(*action, session, view, args.script);
        window.swapBuffers();
        ++frame;
        if (args.frames > 0 && frame >= args.frames) {
            if (!args.screenshot.empty()) {
                writeShownImage(session, view, args.screenshot);
                std::cout << "wrote " << args.screenshot << "\n";
            }
            break;
        }
        if (!args.script.empty() && next >= script.size() && wait == 0 && !session.refining())
            break;
        // Nothing to do: wait for input instead of spinning.
        if (!scripted && session.version() == renderedVersion && !preview && !session.refining())
            glfwWaitEventsTimeout(0.1);
    }
    if (!session.errors().empty() && scripted)
        std::cout << session.errors().size()
                  << " error(s) shown in the panel, last: " << session.errors().back() << "\n";
}

} // namespace

void addViewCommand(CLI::App& app) {
    auto args = std::make_shared<ViewArgs>();
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
    // What runView() reads from the mouse and keyboard; kept here so --help tells the truth.
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
