// `veil view <scene.json>`: explore a scene in a window (GLFW + Dear ImGui): orbit camera,
// switch OIT techniques, tune exposure, lights and ambient, hot-reload shaders, screenshots.
// `--frames N --screenshot out.png` renders N frames, saves the last one and exits, so the
// viewer can be tested (under Xvfb) against `veil render`.
#include "app/commands.h"
#include "app/property_widgets.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "frame/renderer.h"
#include "gpu/window_context.h"
#include "io/image_io.h"
#include "oit/technique.h"
#include "scene/scene.h"
#include "shadows/technique.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <glm/gtc/constants.hpp>

#include <cmath>
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
    int width = 0, height = 0;
    int frames = 0; // 0 = interactive
    std::vector<std::string> overrides;
};

// Orbit around the camera's target: yaw/pitch/distance edited by the mouse.
struct Orbit {
    glm::vec3 target{0.0f};
    float yaw = 0.0f, pitch = 0.0f, distance = 1.0f;

    void from(const scene::Camera& c) {
        target = c.target;
        const glm::vec3 d = c.position - c.target;
        distance = glm::length(d);
        yaw = std::atan2(d.x, d.z);
        pitch = std::asin(glm::clamp(d.y / distance, -1.0f, 1.0f));
    }
    void apply(scene::Camera& c) const {
        const glm::vec3 dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                            std::cos(pitch) * std::cos(yaw));
        c.position = target + dir * distance;
        c.target = target;
        c.up = glm::vec3(0, 1, 0);
    }
};

class ImGuiSession {
public:
    explicit ImGuiSession(GLFWwindow* window) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;
        ImGui_ImplGlfw_InitForOpenGL(window, true);
        ImGui_ImplOpenGL3_Init("#version 450 core");
    }
    ~ImGuiSession() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiSession(const ImGuiSession&) = delete;
    ImGuiSession& operator=(const ImGuiSession&) = delete;
};

void runView(const ViewArgs& args) {
    if (!args.screenshot.empty()) {
        const std::string ext = lowerExtension(args.screenshot);
        VEIL_CHECK(ext == ".png" || ext == ".exr", "--screenshot '{}' must end in .png or .exr",
                   args.screenshot);
        checkOutputPath(args.screenshot, "--screenshot", {args.scene});
    }
    scene::Scene scene = scene::loadScene(args.scene, args.overrides);
    const int width = args.width > 0 ? args.width : scene.render.width;
    const int height = args.height > 0 ? args.height : scene.render.height;
    gpu::WindowContext window(width, height, "veil view: " + args.scene);
    std::string oitName = args.oit.empty() ? scene.render.oit : args.oit;
    scene::Camera camera = scene.camera(args.camera.empty() ? scene.render.camera : args.camera);
    Orbit orbit;
    orbit.from(camera);

    // The technique's property values shown in the panel: the scene's for the scene's
    // technique, else the defaults; reset to the defaults when the technique changes.
    const auto& registry = oit::Registry::instance();
    auto valuesFor = [&](const std::string& name) {
        return registry
            .resolve(name, name == scene.render.oit ? scene.render.oitProperties : nullptr,
                     name == scene.render.oit ? scene.render.oitWhere : "--oit")
            .values();
    };
    nlohmann::json oitValues = valuesFor(oitName);
    // The same for the shadow technique.
    std::string shadowName = args.shadows.empty() ? scene.render.shadows : args.shadows;
    const auto& shadowRegistry = shadows::Registry::instance();
    auto shadowValuesFor = [&](const std::string& name) {
        const bool own = name == scene.render.shadows;
        return shadowRegistry
            .resolve(name, own ? scene.render.shadowProperties : nullptr,
                     own ? scene.render.shadowsWhere : "--shadows")
            .values();
    };
    nlohmann::json shadowValues = shadowValuesFor(shadowName);

    std::unique_ptr<frame::Renderer> renderer;
    int rw = 0, rh = 0;
    auto rebuild = [&] {
        window.framebufferSize(rw, rh);
        if (args.frames > 0) rw = width, rh = height; // scripted: exactly the asked size
        renderer = std::make_unique<frame::Renderer>(
            scene, window.info(),
            frame::RendererOptions{rw, rh, camera.name, oitName, oitValues, shadowName,
                                   shadowValues});
    };
    rebuild();
    std::string goodName = oitName;
    nlohmann::json goodValues = oitValues;
    std::string goodShadowName = shadowName;
    nlohmann::json goodShadowValues = shadowValues;
    gpu::Framebuffer blitSource;
    auto attachBlit = [&] { blitSource.attach(GL_COLOR_ATTACHMENT0, renderer->ldrTexture()); };
    attachBlit();

    std::unique_ptr<ImGuiSession> gui;
    if (args.frames == 0) gui = std::make_unique<ImGuiSession>(window.window());
    const std::vector<std::string> techniques = registry.names();
    const std::vector<std::string> shadowTechniques = shadowRegistry.names();
    int frame = 0;
    std::string status;
    while (!window.shouldClose()) {
        window.pollEvents();
        int fw = 0, fh = 0;
        window.framebufferSize(fw, fh);
        if (args.frames == 0 && (fw != rw || fh != rh) && fw > 0 && fh > 0) {
            rebuild();
            attachBlit();
        }
        bool changed = false;
        if (gui) {
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            ImGuiIO& io = ImGui::GetIO();
            if (!io.WantCaptureMouse) {
                if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
                    orbit.yaw -= io.MouseDelta.x * 0.01f;
                    orbit.pitch = glm::clamp(orbit.pitch + io.MouseDelta.y * 0.01f, -1.5f, 1.5f);
                }
                if (io.MouseWheel != 0.0f) orbit.distance *= std::pow(0.9f, io.MouseWheel);
            }
            ImGui::Begin("Veil");
            ImGui::Text("%s", window.info().renderer.c_str());
            for (const auto& p : renderer->passTimes())
                ImGui::Text("%-12s %7.3f ms", p.name.c_str(), p.milliseconds);
            if (ImGui::BeginCombo("OIT", oitName.c_str())) {
                for (const auto& t : techniques)
                    if (ImGui::Selectable(t.c_str(), t == oitName) && t != oitName) {
                        oitName = t;
                        oitValues = valuesFor(t);
                        changed = true;
                    }
                ImGui::EndCombo();
            }
            // Every declared property of the technique, generated from its schema.
            if (const oit::TechniqueInfo* info = registry.find(oitName);
                info && !info->properties.empty() &&
                ImGui::TreeNodeEx("technique properties", ImGuiTreeNodeFlags_DefaultOpen)) {
                changed = propertyWidgets(info->properties, oitValues) || changed;
                ImGui::TreePop();
            }
            if (ImGui::BeginCombo("shadows", shadowName.c_str())) {
                for (const auto& t : shadowTechniques)
                    if (ImGui::Selectable(t.c_str(), t == shadowName) && t != shadowName) {
                        shadowName = t;
                        shadowValues = shadowValuesFor(t);
                        changed = true;
                    }
                ImGui::EndCombo();
            }
            if (const shadows::TechniqueInfo* info = shadowRegistry.find(shadowName);
                info && !info->properties.empty() &&
                ImGui::TreeNodeEx("shadow properties", ImGuiTreeNodeFlags_DefaultOpen)) {
                changed = propertyWidgets(info->properties, shadowValues) || changed;
                ImGui::TreePop();
            }
            if (ImGui::CollapsingHeader("frame passes")) {
                for (const frame::Pass& p : renderer->passes().passes()) {
                    std::string reads, writes;
                    for (const auto& r : p.reads)
                        reads += (reads.empty() ? "" : ", ") + r;
                    for (const auto& w : p.writes)
                        writes += (writes.empty() ? "" : ", ") + w;
                    ImGui::Text("%-11s %s -> %s", p.name.c_str(), reads.c_str(), writes.c_str());
                }
            }
            if (const nlohmann::json stats = renderer->technique().stats(); !stats.empty())
                ImGui::TextWrapped("stats: %s", stats.dump().c_str());
            if (const nlohmann::json stats = renderer->shadowTechnique().stats(); !stats.empty())
                ImGui::TextWrapped("shadow stats: %s", stats.dump().c_str());
            ImGui::SliderFloat("exposure", &scene.render.exposure, 0.05f, 8.0f, "%.2f",
                               ImGuiSliderFlags_Logarithmic);
            ImGui::ColorEdit3("ambient", &scene.render.ambient.x, ImGuiColorEditFlags_Float);
            for (std::size_t i = 0; i < scene.lights.size(); ++i) {
                ImGui::PushID(static_cast<int>(i));
                ImGui::SliderFloat("light intensity", &scene.lights[i].intensity, 0.0f, 500.0f,
                                   "%.2f", ImGuiSliderFlags_Logarithmic);
                ImGui::PopID();
            }
            if (ImGui::Button("Reload shaders (R)") ||
                (!io.WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_R))) {
                const int failed = renderer->reloadShaders();
                status = failed ? fmt::format("{} program(s) failed: see the log", failed)
                                : "shaders reloaded";
            }
            ImGui::SameLine();
            if (ImGui::Button("Screenshot")) {
                const std::string name = fmt::format("veil-{:04d}.png", frame);
                io::writeImage(name, renderer->readLdr());
                status = "wrote " + name;
            }
            ImGui::TextUnformatted(status.c_str());
            ImGui::End();
        }
        if (changed) {
            try {
                rebuild();
                attachBlit();
                goodName = oitName;
                goodValues = oitValues;
                goodShadowName = shadowName;
                goodShadowValues = shadowValues;
            } catch (const Error& e) {
                // Keep rendering (and showing) what last worked.
                status = e.what();
                oitName = goodName;
                oitValues = goodValues;
                shadowName = goodShadowName;
                shadowValues = goodShadowValues;
            }
        }
        orbit.apply(camera);
        if (args.frames == 0) renderer->setCamera(camera);
        renderer->render();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fw, fh);
        glBlitNamedFramebuffer(blitSource.id(), 0, 0, 0, renderer->width(), renderer->height(), 0,
                               0, fw, fh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        if (gui) {
            ImGui::Render();
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        }
        window.swapBuffers();
        ++frame;
        if (args.frames > 0 && frame >= args.frames) {
            if (!args.screenshot.empty()) {
                io::writeImage(args.screenshot, renderer->readLdr());
                std::cout << "wrote " << args.screenshot << "\n";
            }
            break;
        }
    }
}

} // namespace

void addViewCommand(CLI::App& app) {
    auto args = std::make_shared<ViewArgs>();
    CLI::App* cmd = app.add_subcommand("view", "Explore a scene in a window (needs a display)");
    cmd->add_option("scene", args->scene, "Scene file (JSON)")->required();
    cmd->add_option("--width", args->width, "Window width (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--height", args->height, "Window height (default: the scene's)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--camera", args->camera, "Camera name");
    cmd->add_option("--oit", args->oit, "Transparency technique");
    cmd->add_option("--shadows", args->shadows, "Shadow technique");
    cmd->add_option("--set", args->overrides, "Override a scene value: key=value");
    cmd->add_option("--frames", args->frames,
                    "Render this many frames without the GUI, then exit (for tests)");
    cmd->add_option("--screenshot", args->screenshot, "With --frames: save the last frame");
    // What runView() reads from the mouse and keyboard; kept here so --help tells the truth.
    cmd->footer("Key bindings:\n"
                "  left drag    orbit the camera around the scene\n"
                "  wheel        zoom (orbit distance)\n"
                "  R            reload shaders from disk (failing programs keep the last good)\n"
                "  window close quit\n"
                "The panel switches techniques, edits their properties, exposure, ambient and "
                "lights, and takes screenshots (veil-NNNN.png).");
    cmd->callback([args] { runView(*args); });
}

} // namespace veil::app
