// The viewer's generated property widgets (src/ui/property_widgets.h), driven headless
// through Dear ImGui without a backend: every declared property of every technique gets a
// widget, nothing changes without input, and a click on a checkbox flips its value.
#include "oit/technique.h"
#include "ui/property_widgets.h"

#include <gtest/gtest.h>
#include <imgui.h>

namespace veil::ui {
namespace {

struct HeadlessImGui {
    HeadlessImGui() {
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = ImVec2(800, 2000);
        io.DeltaTime = 1.0f / 60.0f;
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    }
    ~HeadlessImGui() { ImGui::DestroyContext(); }
    // One frame of the widgets; `click` presses the mouse at a point.
    bool frame(const PropertySchema& schema, nlohmann::json& values, ImVec2 mouse = {-1, -1},
               bool down = false) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = mouse; // Dear ImGui 1.86 (Debian 12): no input-event queue yet
        io.MouseDown[0] = down;
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImVec2(800, 2000));
        ImGui::Begin("t");
        const bool changed = propertyWidgets(schema, values);
        firstItem = ImGui::GetItemRectMin(); // the last widget's rectangle
        ImGui::End();
        ImGui::Render();
        return changed;
    }
    ImVec2 firstItem;
};

TEST(PropertyWidgetsTest, EveryPropertyOfEveryTechniqueGetsAWidget) {
    HeadlessImGui gui;
    const auto& registry = oit::Registry::instance();
    for (const auto& t : registry.all()) {
        nlohmann::json values = nlohmann::json::object();
        EXPECT_FALSE(gui.frame(t.properties, values)) << t.name;
        // Each widget filled in its property's default: the values are the technique's.
        EXPECT_EQ(values, registry.resolve(t.name, nlohmann::json(), "t").values()) << t.name;
    }
}

TEST(PropertyWidgetsTest, ClickingACheckboxFlipsIt) {
    HeadlessImGui gui;
    PropertySchema schema;
    schema.boolean("on", false, "a switch");
    nlohmann::json values = schema.defaults().values();
    gui.frame(schema, values); // lay out once to learn where the checkbox is
    const ImVec2 at(gui.firstItem.x + 5, gui.firstItem.y + 5);
    gui.frame(schema, values, at, true);
    const bool changed = gui.frame(schema, values, at, false); // release = click
    EXPECT_TRUE(changed);
    EXPECT_EQ(values["on"], true);
    // And the edited values still satisfy the schema.
    EXPECT_NO_THROW(schema.resolve(values, "t"));
}

} // namespace
} // namespace veil::ui
