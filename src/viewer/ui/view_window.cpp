// `veil view`'s window and its loop (view_window.h).
#include "viewer/ui/view_window.h"

#include "viewer/debug_view.h"
#include "viewer/screenshot.h"
#include "viewer/session/timeline_player.h"
#include "viewer/session/view_session.h"
#include "viewer/ui/timeline_panel.h"
#include "viewer/ui/view_panel.h"
#include "viewer/view_script_run.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/log.h"
#include "base/text.h"
#include "gpu/window_context.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

namespace veil::ui {

namespace fs = std::filesystem;

namespace {

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
void sceneSize(const ViewerOptions& o, int& w, int& h) {
    w = o.width;
    h = o.height;
    if (w > 0 && h > 0) return;
    int sw = 640, sh = 360;
    if (lowerExtension(o.scene) != ".vdb") {
        const scene::Scene s = scene::loadScene(o.scene, o.overrides);
        sw = s.render.width;
        sh = s.render.height;
    } else {
        sw = sh = 512;
    }
    if (w <= 0) w = sw;
    if (h <= 0) h = sh;
}

// The interactive camera: left drag orbits, right or middle drag pans, the wheel zooms, R
// reloads the shaders (unless the panel has the mouse or the keyboard). Returns whether the
// camera moved.
bool cameraInput(session::ViewSession& session) {
    ImGuiIO& io = ImGui::GetIO();
    bool moving = false;
    if (!io.WantCaptureMouse) {
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
    if (!io.WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_R)) session.reloadShaders();
    return moving;
}

// Fits `shown` into the window's fw x fh framebuffer with its aspect, over a dark background.
void present(const gpu::Texture& shown, int fw, int fh, bool nearest) {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fw, fh);
    const float bg[4] = {0.08f, 0.08f, 0.09f, 1.0f};
    glClearNamedFramebufferfv(0, GL_COLOR, 0, bg);
    if (!shown) return;
    gpu::Framebuffer source;
    source.attach(GL_COLOR_ATTACHMENT0, shown);
    const double s = std::min(double(fw) / shown.width(), double(fh) / shown.height());
    const int w = int(std::lround(shown.width() * s)), h = int(std::lround(shown.height() * s));
    const int x0 = (fw - w) / 2, y0 = (fh - h) / 2;
    glBlitNamedFramebuffer(source.id(), 0, 0, 0, shown.width(), shown.height(), x0, y0, x0 + w,
                           y0 + h, GL_COLOR_BUFFER_BIT,
                           nearest || s == 1.0 ? GL_NEAREST : GL_LINEAR);
}

} // namespace

void runViewer(const ViewerOptions& o) {
    std::vector<viewer::ScriptAction> script;
    if (!o.script.empty()) script = viewer::loadViewScript(o.script);
    viewer::ScriptRunner runner(std::move(script), o.script);
    const bool scripted = o.frames > 0 || !o.script.empty();

    int width = 0, height = 0;
    sceneSize(o, width, height);
    // Interactive: room for the panel beside a small scene; scripted: the frame size exactly.
    const int ww = o.windowWidth > 0 ? o.windowWidth : scripted ? width : std::max(width, 1280);
    const int wh = o.windowHeight > 0 ? o.windowHeight : scripted ? height : std::max(height, 720);
    gpu::WindowContext window(ww, wh, "veil view: " + o.scene);
    int fw = 0, fh = 0;
    window.framebufferSize(fw, fh);
    session::ViewSession session(window.info(), o.scene, o.overrides, o.camera,
                                 scripted ? width : fw, scripted ? height : fh);
    // Command-line choices are part of the start: a bad one is the command's error.
    if (!o.oit.empty() && !session.selectOit(o.oit)) throw Error(session.lastError());
    if (!o.shadows.empty() && !session.selectShadows(o.shadows)) throw Error(session.lastError());
    session.setReuseShadowMaps(o.reuseShadowMaps);
    session.setRefineTilePx(o.refineTilePx >= 0                           ? o.refineTilePx
                            : !scripted && window.info().softwareRenderer ? 128
                                                                          : 0);
    session.setRefineBudgetMs(o.refineBudgetMs >= 0.0 ? o.refineBudgetMs : scripted ? 0.0 : 100.0);
    session.setProgressiveBake(!scripted);

    // The timeline of an animated scene (made again when another scene is opened).
    auto timeline = std::make_unique<session::TimelinePlayer>(session);
    fs::path timelineScene = session.scenePath();
    auto lastTick = std::chrono::steady_clock::now();

    std::unique_ptr<ImGuiSession> gui;
    if (o.frames == 0) gui = std::make_unique<ImGuiSession>(window.window(), !scripted);
    glfwSetDropCallback(window.window(), onDrop);

    viewer::DebugView view;
    PanelState panel;
    std::uint64_t renderedVersion = ~std::uint64_t(0);
    std::string renderedView = "\x01";
    int renderedLayer = -1;
    std::string shownView; // the debug view the last update showed
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
        const bool force = runner.beforeFrame({session, view, *timeline, panel.expand});
        if (gui) {
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            const bool moving = !scripted && cameraInput(session);
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
        present(view.active() ? view.texture() : session.displayTexture(), fw, fh, view.active());
        if (gui) {
            ImGui::Render();
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            gui->saveLayout();
        }
        runner.afterFrame(session, view, fw, fh);
        window.swapBuffers();
        ++frame;
        if (o.frames > 0 && frame >= o.frames) {
            if (!o.screenshot.empty()) {
                viewer::writeShownImage(session, view, o.screenshot);
                std::cout << "wrote " << o.screenshot << "\n";
            }
            break;
        }
        if (runner.finished(session)) break;
        // Nothing to do: wait for input instead of spinning.
        if (!scripted && session.version() == renderedVersion && !preview && !session.refining())
            glfwWaitEventsTimeout(0.1);
    }
    if (!session.errors().empty() && scripted)
        std::cout << session.errors().size()
                  << " error(s) shown in the panel, last: " << session.errors().back() << "\n";
}

} // namespace veil::ui
