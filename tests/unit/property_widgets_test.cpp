// The viewer's generated property widgets (src/viewer/ui/property_widgets.h), driven headless
// through Dear ImGui without a backend: every declared property of every technique gets a
// widget, nothing changes without input, a click on a checkbox flips its value, the form
// layout keeps labels whole and a colour's fields wide enough for their values, hidden keys
// (a volume's temperature settings without a temperature grid) get no widget, and the
// timeline's slider names its range.
#include "oit/technique.h"
#include "scene/value_properties.h"
#include "viewer/ui/property_widgets.h"
#include "viewer/ui/timeline_panel.h"
#include "viewer/ui/view_panel.h"

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
               bool down = false, float width = 800) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = mouse; // Dear ImGui 1.86 (Debian 12): no input-event queue yet
        io.MouseDown[0] = down;
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImVec2(width, 2000));
        ImGui::Begin("t");
        contentMin = ImGui::GetCursorScreenPos();
        contentMaxX = contentMin.x + ImGui::GetContentRegionAvail().x;
        const bool changed = propertyWidgets(schema, values);
        firstItem = ImGui::GetItemRectMin(); // the last widget's rectangle
        lastItemMax = ImGui::GetItemRectMax();
        ImGui::End();
        ImGui::Render();
        return changed;
    }
    ImVec2 firstItem, lastItemMax, contentMin;
    float contentMaxX = 0;
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

// The form layout: the whole key in a label column as wide as the longest key, the widget
// beside it up to the panel's edge; in a panel too narrow for both, the widget goes below.
TEST(PropertyWidgetsTest, LabelsAreWholeAndWidgetsFillTheRestOfTheLine) {
    HeadlessImGui gui;
    PropertySchema schema;
    schema.integer("n", 4, 1, 64, "short key");
    schema.real("initial_nodes_per_pixel", 4.0, 0.0, 100.0, "a long key");
    nlohmann::json values = schema.defaults().values();
    gui.frame(schema, values); // the font is set up by a first frame
    const float longest = ImGui::CalcTextSize("initial_nodes_per_pixel").x;
    const float spacing = ImGui::GetStyle().ItemSpacing.x, em = ImGui::GetFontSize();
    for (float width : {300.0f, 420.0f, 800.0f}) {
        gui.frame(schema, values, {-1, -1}, false, width);
        // The last widget (the long key's) starts after the whole label and ends at the edge.
        EXPECT_GE(gui.firstItem.x, gui.contentMin.x + longest + spacing - 0.5f) << width;
        EXPECT_NEAR(gui.lastItemMax.x, gui.contentMaxX, 1.0f) << width;
        EXPECT_GE(gui.lastItemMax.x - gui.firstItem.x, 6 * em - 1.0f) << width;
        // Beside its label: on the second row of the form.
        EXPECT_LT(gui.firstItem.y, gui.contentMin.y + 2.5f * ImGui::GetFrameHeightWithSpacing());
    }
    // Too narrow for label and widget: the widget takes the line below, full width.
    gui.frame(schema, values, {-1, -1}, false, longest + 4 * em);
    EXPECT_NEAR(gui.firstItem.x, gui.contentMin.x, 1.0f);
    EXPECT_GT(gui.firstItem.y, gui.contentMin.y + 2.5f * ImGui::GetFrameHeightWithSpacing());
}

// A colour beside a long key: each of its three fields holds what it shows ("R:0.550") at
// every panel width, else the colour takes the line below the key.
TEST(PropertyWidgetsTest, ColourFieldsAreWholeBesideALongLabel) {
    HeadlessImGui gui;
    PropertySchema schema;
    schema.color("a_long_key_of_a_volume_colour", glm::vec3(0.55f), "a colour");
    nlohmann::json values = schema.defaults().values();
    gui.frame(schema, values);
    const ImGuiStyle& style = ImGui::GetStyle();
    const float field = ImGui::CalcTextSize("R:0.550").x + 2 * style.FramePadding.x;
    for (float width = 240; width <= 800; width += 10) {
        gui.frame(schema, values, {-1, -1}, false, width);
        const float fields = gui.lastItemMax.x - gui.firstItem.x - ImGui::GetFrameHeight() -
                             3 * style.ItemInnerSpacing.x;
        EXPECT_GE(fields / 3, field - 0.5f) << "panel " << width;
    }
}

TEST(PropertyWidgetsTest, HiddenKeysGetNoWidget) {
    HeadlessImGui gui;
    scene::VolumeRef cold;
    const std::vector<std::string> hidden = hiddenVolumeKeys(cold);
    EXPECT_EQ(hidden, (std::vector<std::string>{"temperature_scale", "temperature_offset",
                                                "temperature_intensity"}));
    scene::VolumeRef fire;
    fire.temperatureGrid = "temperature";
    EXPECT_TRUE(hiddenVolumeKeys(fire).empty());
    // A widget fills in its key's value; the hidden ones are left out.
    nlohmann::json values = nlohmann::json::object();
    gui.frame(scene::volumeProperties(), values);
    EXPECT_TRUE(values.contains("temperature_scale")) << values.dump();
    values = nlohmann::json::object();
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = {-1, -1};
    ImGui::NewFrame();
    ImGui::Begin("t");
    propertyWidgets(scene::volumeProperties(), values, hidden);
    ImGui::End();
    ImGui::Render();
    EXPECT_TRUE(values.contains("density_scale")) << values.dump();
    for (const std::string& key : hidden)
        EXPECT_FALSE(values.contains(key)) << key << ": " << values.dump();
}

TEST(PropertyWidgetsTest, TimelineSliderNamesItsRange) {
    EXPECT_EQ(timelineSliderFormat({1, 240, 1}), "frame %d of 1-240");
    EXPECT_EQ(timelineSliderFormat({0, 100, 5}), "frame %d of 0-100:5");
    EXPECT_EQ(timelineSliderFormat({-5, -1, 1}), "frame %d of -5--1");
}

} // namespace
} // namespace veil::ui
