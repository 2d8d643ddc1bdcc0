#include "viewer/ui/view_panel.h"

#include "viewer/screenshot.h"
#include "viewer/ui/property_widgets.h"

#include "base/error.h"
#include "capture/dump.h"
#include "oit/technique.h"
#include "scene/value_properties.h"
#include "shadows/technique.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cfloat>
#include <filesystem>

namespace veil::ui {

namespace fs = std::filesystem;

namespace {

const ImVec4 kErrorColour(1.0f, 0.45f, 0.35f, 1.0f);

void tip(const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", text);
}

bool section(const char* name, const PanelState& state, bool defaultOpen = false) {
    // A script's {"expand": [...]} opens exactly the sections it lists.
    if (!state.expand.empty()) ImGui::SetNextItemOpen(state.expand.count(name) > 0);
    return ImGui::CollapsingHeader(name, defaultOpen ? ImGuiTreeNodeFlags_DefaultOpen : 0);
}

// The next button on this line if it fits in the panel, else on a line of its own.
void sameLineIfFits(const char* nextLabel) {
    const float w =
        ImGui::CalcTextSize(nextLabel, nullptr, true).x + ImGui::GetStyle().FramePadding.x * 2.0f;
    const float right = ImGui::GetItemRectMax().x + ImGui::GetStyle().ItemSpacing.x + w;
    if (right <= ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x) ImGui::SameLine();
}

// An input filling the line but for a button `buttonLabel` after it.
void widthBeforeButton(const char* buttonLabel) {
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - ImGui::CalcTextSize(buttonLabel).x -
                            ImGui::GetStyle().FramePadding.x * 2.0f -
                            ImGui::GetStyle().ItemSpacing.x);
}

std::string jsonVec(const glm::vec3& v) {
    return nlohmann::json::array({double(v.x), double(v.y), double(v.z)}).dump();
}

// The generated widgets of a schema over `values`; each changed key is set as prefix.KEY.
void schemaWidgets(session::ViewSession& s, const PropertySchema& schema, nlohmann::json values,
                   const std::string& prefix, const std::vector<std::string>& hidden = {}) {
    if (schema.empty()) return;
    const nlohmann::json before = values;
    if (propertyWidgets(schema, values, hidden))
        for (const auto& [key, v] : values.items())
            if (!before.contains(key) || before[key] != v)
                s.set(prefix + "." + key + "=" + v.dump());
}

template <class Registry>
void techniqueCombo(session::ViewSession& s, const char* label, const Registry& registry,
                    const std::string& rendering, bool isOit) {
    formLabel(label, labelColumnWidth({label}),
              "the technique rendering now; greyed ones are not available on this driver");
    if (!ImGui::BeginCombo((std::string("##") + label).c_str(), rendering.c_str())) return;
    for (const auto& t : registry.all()) {
        const bool available = isOit ? s.oitAvailable(t.name) : s.shadowsAvailable(t.name);
        ImGui::BeginDisabled(!available);
        if (ImGui::Selectable(t.name.c_str(), t.name == rendering) && t.name != rendering)
            isOit ? s.selectOit(t.name) : s.selectShadows(t.name);
        ImGui::EndDisabled();
        const std::string why = available ? t.description
                                          : fmt::format("not available on this GL driver ({}): {}",
                                                        s.context().renderer, t.description);
        tip(why.c_str());
    }
    ImGui::EndCombo();
}

void fileSection(GLFWwindow* window, session::ViewSession& s, const viewer::DebugView& view,
                 PanelState& st) {
    if (!section("File", st, true)) return;
    ImGui::TextWrapped("%s", s.scenePath().string().c_str());
    if (ImGui::Button("Open...")) st.openDialog.open(fs::absolute(s.scenePath()).parent_path());
    tip("a scene (.json) or an OpenVDB file (.vdb); files dropped on the window open too");
    sameLineIfFits("Reload shaders (R)");
    if (ImGui::Button("Reload shaders (R)")) s.reloadShaders();
    sameLineIfFits("Copy render command");
    if (ImGui::Button("Copy render command")) {
        st.copiedCommand = s.renderCommand();
        glfwSetClipboardString(window, st.copiedCommand.c_str());
    }
    tip("the `veil render` line of this view: --set overrides for every edit and the camera");
    if (!st.copiedCommand.empty()) ImGui::TextWrapped("%s", st.copiedCommand.c_str());
    widthBeforeButton("Save scene as");
    ImGui::InputText("##saveas", &st.saveAs);
    ImGui::SameLine();
    if (ImGui::Button("Save scene as")) s.saveSceneAs(st.saveAs);
    widthBeforeButton("Screenshot");
    ImGui::InputText("##shots", &st.screenshotFolder);
    ImGui::SameLine();
    if (ImGui::Button("Screenshot")) {
        try {
            s.setStatus("wrote " +
                        viewer::screenshotPair(s, view, st.screenshotFolder, st.screenshotCount++));
        } catch (const Error& e) {
            s.fail(e.what());
        }
    }
    tip("PNG of the shown image and EXR beside it (linear HDR, or a debug view's raw values)");
}

void cameraSection(session::ViewSession& s, const PanelState& st) {
    if (!section("Camera", st)) return;
    const scene::Scene& sc = s.scene();
    formLabel("camera", labelColumnWidth({"camera"}));
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - ImGui::CalcTextSize("Reset").x -
                            ImGui::GetFontSize() * 1.5f);
    if (ImGui::BeginCombo("##camera", s.cameraName().c_str())) {
        for (const auto& c : sc.cameras)
            if (ImGui::Selectable(c.name.c_str(), c.name == s.cameraName())) s.selectCamera(c.name);
        ImGui::EndCombo();
    }
    ImGui::SameLine();
    if (ImGui::Button("Reset")) s.resetCamera();
    std::size_t index = 0;
    for (std::size_t i = 0; i < sc.cameras.size(); ++i)
        if (sc.cameras[i].name == s.cameraName()) index = i;
    const scene::Camera& c = sc.cameras[index];
    schemaWidgets(s, scene::cameraProperties(c.type), scene::cameraValues(c),
                  fmt::format("cameras.{}", index));
    ImGui::TextDisabled("left drag: orbit, right/middle drag: pan, wheel: zoom");
}

void renderSection(session::ViewSession& s, const PanelState& st) {
    if (!section("Render", st)) return;
    schemaWidgets(s, scene::renderOutputProperties(), scene::renderOutputValues(s.scene().render),
                  "render");
}

void techniqueSections(session::ViewSession& s, const PanelState& st) {
    const frame::Renderer& r = s.renderer();
    if (section("Transparency (OIT)", st, true)) {
        techniqueCombo(s, "OIT", oit::Registry::instance(), r.oitName(), true);
        if (const oit::TechniqueInfo* info = oit::Registry::instance().find(r.oitName()))
            schemaWidgets(s, info->properties, r.technique().properties().values(), "render.oit");
        if (const nlohmann::json stats = r.technique().stats(); !stats.empty()) {
            ImGui::TextDisabled("statistics of the last frame");
            jsonTable("oit stats", stats);
        }
    }
    if (section("Shadows", st)) {
        const std::string name = r.shadowTechnique().name();
        techniqueCombo(s, "shadows", shadows::Registry::instance(), name, false);
        if (const shadows::TechniqueInfo* info = shadows::Registry::instance().find(name))
            schemaWidgets(s, info->properties, r.shadowTechnique().properties().values(),
                          "render.shadows");
        if (const nlohmann::json stats = r.shadowTechnique().stats(); !stats.empty()) {
            ImGui::TextDisabled("statistics of the last frame");
            jsonTable("shadow stats", stats);
        }
    }
}

void fogSections(session::ViewSession& s, const PanelState& st) {
    const scene::Scene& sc = s.scene();
    if (sc.volumes.empty()) return;
    if (section("Fog marcher", st)) {
        schemaWidgets(s, scene::fogMarcherProperties(), scene::fogMarcherValues(sc.render),
                      "render");
    }
    if (section("Volumes", st)) {
        for (std::size_t i = 0; i < sc.volumes.size(); ++i) {
            const scene::VolumeRef& v = sc.volumes[i];
            ImGui::PushID(static_cast<int>(i));
            const std::string key = fmt::format("volumes.{}.", i);
            ImGui::Separator();
            ImGui::TextUnformatted(v.name.empty() ? key.c_str() : v.name.c_str());
            schemaWidgets(s, scene::volumeProperties(), scene::volumeValues(v),
                          fmt::format("volumes.{}", i), hiddenVolumeKeys(v));
            ImGui::PopID();
        }
    }
}

void lightSection(session::ViewSession& s, const PanelState& st) {
    const scene::Scene& sc = s.scene();
    if (sc.lights.empty() || !section("Lights", st)) return;
    const nlohmann::json& doc = s.sourceDocument();
    for (std::size_t i = 0; i < sc.lights.size(); ++i) {
        const scene::Light& l = sc.lights[i];
        ImGui::PushID(static_cast<int>(i));
        const std::string key = fmt::format("lights.{}.", i);
        ImGui::Separator();
        ImGui::TextUnformatted(l.name.empty() ? key.c_str() : l.name.c_str());
        schemaWidgets(s, scene::lightProperties(l.type), scene::lightValues(l),
                      fmt::format("lights.{}", i));
        if (l.type != scene::LightType::Point) {
            // The document names the aim as a target or a direction; the edit keeps its form.
            const bool hasTarget = doc.is_object() && doc.contains("lights") &&
                                   doc["lights"].is_array() && i < doc["lights"].size() &&
                                   doc["lights"][i].is_object() &&
                                   doc["lights"][i].contains("target");
            glm::vec3 dir = l.direction;
            formLabel("direction", labelColumnWidth({"direction"}));
            if (ImGui::DragFloat3("##direction", &dir.x, 0.01f) && glm::length(dir) > 1e-6f) {
                dir = glm::normalize(dir);
                if (hasTarget)
                    s.set(key + "target=" + jsonVec(l.position + dir));
                else
                    s.set(key + "direction=" + jsonVec(dir));
            }
            tip("direction the light travels (a move recomputes its shadow maps and the fog's "
                "light transmittance volumes)");
        }
        ImGui::PopID();
    }
}

// The heat map's ramp from 0 to `max` (fragments per pixel) as a bar with its ends labelled.
void heatLegend(float max) {
    const float width = ImGui::GetContentRegionAvail().x, height = ImGui::GetFontSize();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    constexpr int kSteps = 20;
    for (int i = 0; i < kSteps; ++i) {
        const glm::vec3 a = viewer::heatRamp(float(i) / kSteps),
                        b = viewer::heatRamp(float(i + 1) / kSteps);
        const ImU32 ca = ImGui::GetColorU32(ImVec4(a.r, a.g, a.b, 1.0f)),
                    cb = ImGui::GetColorU32(ImVec4(b.r, b.g, b.b, 1.0f));
        draw->AddRectFilledMultiColor(ImVec2(p.x + width * i / kSteps, p.y),
                                      ImVec2(p.x + width * (i + 1) / kSteps, p.y + height), ca, cb,
                                      cb, ca);
    }
    ImGui::Dummy(ImVec2(width, height));
    ImGui::Text("0");
    const std::string label = fmt::format("{:g} fragments per pixel (max)", max);
    ImGui::SameLine(std::max(0.0f, width - ImGui::CalcTextSize(label.c_str()).x));
    ImGui::TextUnformatted(label.c_str());
}

void debugSection(session::ViewSession& s, viewer::DebugView& view, const PanelState& st) {
    if (!section("Debug view", st)) return;
    if (ImGui::RadioButton("frame", !view.active())) view.select("");
    for (const viewer::DebugViewEntry& e : viewer::debugViewEntries(s.renderer())) {
        ImGui::BeginDisabled(!e.reason.empty());
        if (ImGui::RadioButton(e.resource.c_str(), view.resource() == e.resource))
            view.select(e.resource, 0);
        ImGui::EndDisabled();
        const std::string info =
            e.reason.empty()
                ? fmt::format("{} x{} layer(s), {}\n{}", e.format, e.layers,
                              e.bytes >= 1 << 20 ? fmt::format("{:.1f} MiB", e.bytes / 1048576.0)
                                                 : fmt::format("{:.1f} KiB", e.bytes / 1024.0),
                              capture::resourceUnits(e.resource))
                : e.reason;
        tip(info.c_str());
        if (view.resource() == e.resource && e.layers > 1) {
            int layer = view.layer();
            ImGui::Indent();
            if (ImGui::SliderInt("layer / slice", &layer, 0, e.layers - 1))
                view.select(e.resource, layer);
            ImGui::Unindent();
        }
    }
    // The viewer's own view: the frame against `reference`, rendered only while shown.
    if (ImGui::RadioButton(viewer::kReferenceErrorView, view.errorView()))
        view.select(viewer::kReferenceErrorView);
    tip("|frame - reference| of the linear HDR radiance per RGB channel: the same frame "
        "rendered by a second renderer with the exact sorted composite (only while shown)");
    if (view.errorView() && view.error())
        ImGui::Text("RMSE %.4g, max %.4g (linear radiance)", view.error()->error().rmse,
                    view.error()->maxAbs());
    if (view.heatMap()) {
        heatLegend(view.hi());
    } else if (view.active()) {
        ImGui::Text("shown range [%.4g, %.4g] -> black..white", view.lo(), view.hi());
    }
}

void frameSection(session::ViewSession& s, PanelState& st) {
    if (!section("Frame", st, true)) return;
    const frame::Renderer& r = s.renderer();
    ImGui::TextWrapped("%s", s.context().renderer.c_str());
    // view.refine_tile_px: full-size frames refined in tiles, one per UI frame (0 = off).
    const float labels =
        labelColumnWidth({"refine_tile_px", "refine_budget_ms", "reuse_shadow_maps"});
    const char* tileTip = "Refine full-size frames in tiles of this many pixels, one tile per UI "
                          "frame, showing the last complete image meanwhile (0 = in one piece)";
    int tile = s.refineTilePx();
    formLabel("refine_tile_px", labels, tileTip);
    if (ImGui::InputInt("##refine_tile_px", &tile, 32, 128, ImGuiInputTextFlags_EnterReturnsTrue))
        s.setRefineTilePx(std::max(0, tile));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tileTip);
    // view.refine_budget_ms: a step's tile halved until its estimated pass time fits.
    float budget = static_cast<float>(s.refineBudgetMs());
    const std::string budgetTip =
        fmt::format("Halve a refinement step's tile (down to {} px) until its estimated pass "
                    "time is under this many ms (0 = whole tiles)",
                    session::ViewSession::kMinRefineTilePx);
    formLabel("refine_budget_ms", labels, budgetTip);
    if (ImGui::InputFloat("##refine_budget_ms", &budget, 10.0f, 100.0f, "%.0f",
                          ImGuiInputTextFlags_EnterReturnsTrue))
        s.setRefineBudgetMs(std::max(0.0f, budget));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", budgetTip.c_str());
    // view.reuse_shadow_maps: camera moves keep the shadow maps (edits redraw them).
    bool reuse = s.reusesShadowMaps();
    formLabel("reuse_shadow_maps", labels);
    if (ImGui::Checkbox("##reuse_shadow_maps", &reuse)) s.setReuseShadowMaps(reuse);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Keep the shadow maps across frames while nothing they depend on "
                          "changed (camera moves keep them; %s)",
                          r.shadowTechnique().dependsOnCamera()
                              ? "this technique follows the camera and redraws every frame"
                              : "this technique's maps do not depend on the camera");
    if (r.refining())
        ImGui::Text("refining: %.0f%% (%d px tiles)",
                    100.0 * double(r.refinement().pixelsDone) / double(r.refinement().pixels),
                    s.nextRefineTilePx());
    ImGui::Text("%d x %d, timer: %s", r.width(), r.height(),
                r.timerMode() == gpu::GpuTimer::Mode::Query ? "GL_TIME_ELAPSED"
                                                            : "glFinish + CPU clock");
    if (!st.frameMs.empty()) {
        const std::vector<float> v(st.frameMs.begin(), st.frameMs.end());
        const float last = v.back();
        ImGui::PlotLines("##frame", v.data(), static_cast<int>(v.size()), 0,
                         fmt::format("{:.2f} ms", last).c_str(), 0.0f,
                         *std::max_element(v.begin(), v.end()) * 1.1f,
                         ImVec2(0, ImGui::GetFontSize() * 3));
    }
    if (ImGui::TreeNodeEx("pass times", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (ImGui::BeginTable("passes", 2, ImGuiTableFlags_SizingStretchProp)) {
            for (const auto& p : r.passTimes()) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(p.name.c_str());
                ImGui::TableNextColumn();
                ImGui::Text("%8.3f ms", p.milliseconds);
            }
            ImGui::EndTable();
        }
        ImGui::TreePop();
    }
    if (ImGui::TreeNode("gpu memory", "GPU memory %.1f MiB", r.gpuBytes() / 1048576.0)) {
        // oit.accumulation is the technique's whole storage; its declared targets
        // (oit.<technique>.*) are listed too, indented, and are not added to the total again.
        for (const viewer::DebugViewEntry& e : viewer::debugViewEntries(r)) {
            if (e.bytes == 0) continue;
            const bool target =
                e.resource.rfind("oit.", 0) == 0 && e.resource != "oit.accumulation";
            ImGui::Text("%s%-*s %9.1f KiB", target ? "  " : "", target ? 24 : 26,
                        e.resource.c_str(), e.bytes / 1024.0);
        }
        if (const volume::FogPass* fog = r.fog())
            for (std::size_t i = 0; i < fog->stats().size(); ++i)
                ImGui::Text("volume %-19zu %9.1f KiB", i, fog->stats()[i].gpuBytes / 1024.0);
        ImGui::TreePop();
    }
    if (ImGui::TreeNode("passes and resources")) {
        for (const frame::Pass& p : r.passes().passes()) {
            std::string reads, writes;
            for (const auto& x : p.reads)
                reads += (reads.empty() ? "" : ", ") + x;
            for (const auto& x : p.writes)
                writes += (writes.empty() ? "" : ", ") + x;
            ImGui::TextWrapped("%s: %s -> %s", p.name.c_str(), reads.c_str(), writes.c_str());
        }
        ImGui::TreePop();
    }
}

} // namespace

std::vector<std::string> hiddenVolumeKeys(const scene::VolumeRef& volume) {
    if (!volume.temperatureGrid.empty()) return {};
    return {"temperature_scale", "temperature_offset", "temperature_intensity"};
}

void drawPanel(GLFWwindow* window, session::ViewSession& session, viewer::DebugView& view,
               PanelState& state) {
    const float em = ImGui::GetFontSize();
    ImGui::SetNextWindowPos(ImVec2(em * 0.5f, em * 0.5f), ImGuiCond_FirstUseEver);
    // The panel's first size: 24 em wide (about a quarter of a 1280 px window), the window's
    // height. Drag its right edge to resize it; the size is kept between runs (imgui.ini).
    ImGui::SetNextWindowSize(ImVec2(em * 24, ImGui::GetIO().DisplaySize.y - em),
                             ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSizeConstraints(ImVec2(em * 14, em * 6), ImVec2(FLT_MAX, FLT_MAX));
    ImGui::Begin("Veil");
    if (!session.lastError().empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(kErrorColour, "%s", session.lastError().c_str());
        ImGui::PopTextWrapPos();
    } else if (!session.status().empty()) {
        ImGui::TextWrapped("%s", session.status().c_str());
    }
    if (session.errors().size() > 0 &&
        ImGui::TreeNode("errors", "errors (%zu)", session.errors().size())) {
        for (const std::string& e : session.errors())
            ImGui::TextWrapped("%s", e.c_str());
        ImGui::TreePop();
    }
    fileSection(window, session, view, state);
    techniqueSections(session, state);
    fogSections(session, state);
    lightSection(session, state);
    renderSection(session, state);
    cameraSection(session, state);
    debugSection(session, view, state);
    frameSection(session, state);
    ImGui::End();
    if (const auto chosen = state.openDialog.draw()) session.open(*chosen);
}

} // namespace veil::ui
