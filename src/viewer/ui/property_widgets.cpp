#include "viewer/ui/property_widgets.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>

namespace veil::ui {

namespace {

std::string tipText(const PropertyDecl& d) {
    std::string text = d.doc;
    if (!d.citation.empty()) text += "\n" + d.citation;
    if (const std::string range = d.rangeText(); !range.empty()) text += "\nrange " + range;
    return text;
}

void tooltip(const PropertyDecl& d) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tipText(d).c_str());
}

// Drag speed for a float: a hundredth of the value's magnitude (or of the range).
float speedFor(double value, const PropertyDecl& d) {
    double scale = std::fabs(value);
    if (std::isfinite(d.max) && std::isfinite(d.min))
        scale = std::max(scale, (d.max - d.min) / 100.0);
    return static_cast<float>(std::max(scale * 0.01, 1e-7));
}

// Dotted key, printable value pairs of a JSON object.
void flatten(const nlohmann::json& j, const std::string& prefix,
             std::vector<std::pair<std::string, std::string>>& rows) {
    if (j.is_object()) {
        for (const auto& [k, v] : j.items())
            flatten(v, prefix.empty() ? k : prefix + "." + k, rows);
        return;
    }
    std::string text;
    if (j.is_number_float()) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.4g", j.get<double>());
        text = buf;
    } else if (j.is_string()) {
        text = j.get<std::string>();
    } else {
        text = j.dump();
    }
    rows.emplace_back(prefix, text);
}

bool floatWidget(const PropertyDecl& d, const std::string& id, nlohmann::json& v) {
    double x = v.get<double>();
    const double lo = std::isfinite(d.min) ? d.min : -1e30,
                 hi = std::isfinite(d.max) ? d.max : 1e30;
    const bool changed = ImGui::DragScalar(id.c_str(), ImGuiDataType_Double, &x, speedFor(x, d),
                                           &lo, &hi, "%.6g", ImGuiSliderFlags_AlwaysClamp);
    if (changed) v = std::clamp(x, lo, hi);
    return changed;
}

} // namespace

bool propertyWidgets(const PropertySchema& schema, nlohmann::json& values,
                     const std::vector<std::string>& hidden) {
    const auto shown = [&](const PropertyDecl& d) {
        return std::find(hidden.begin(), hidden.end(), d.key) == hidden.end();
    };
    bool any = false;
    std::vector<std::string> keys;
    for (const PropertyDecl& d : schema.all())
        if (shown(d)) keys.push_back(d.key);
    const float width = labelColumnWidth(keys);
    for (const PropertyDecl& d : schema.all()) {
        if (!shown(d)) continue;
        nlohmann::json& v = values[d.key];
        if (v.is_null()) v = d.defaultValue;
        bool changed = false;
        formLabel(d.key, width, tipText(d), minimumWidgetWidth(d.type));
        const std::string id = "##" + d.key;
        switch (d.type) {
        case PropertyType::Bool: {
            bool b = v.get<bool>();
            if ((changed = ImGui::Checkbox(id.c_str(), &b))) v = b;
            break;
        }
        case PropertyType::Int: {
            int i = static_cast<int>(v.get<long long>());
            const int lo = static_cast<int>(std::max(d.min, -1e9));
            const int hi = static_cast<int>(std::min(d.max, 1e9));
            changed = hi - lo <= 256 ? ImGui::SliderInt(id.c_str(), &i, lo, hi)
                                     : ImGui::DragInt(id.c_str(), &i, 1.0f, lo, hi);
            if (changed) v = std::clamp(i, lo, hi);
            break;
        }
        case PropertyType::Float:
            changed = floatWidget(d, id, v);
            break;
        case PropertyType::Vec3:
        case PropertyType::Color: {
            float c[3] = {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
            changed = d.type == PropertyType::Color
                          ? ImGui::ColorEdit3(id.c_str(), c,
                                              ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR)
                          : ImGui::DragFloat3(id.c_str(), c, 0.01f);
            if (changed)
                for (int k = 0; k < 3; ++k)
                    v[k] = std::clamp(static_cast<double>(c[k]), d.min, d.max);
            break;
        }
        case PropertyType::Enum: {
            const std::string current = v.get<std::string>();
            if (ImGui::BeginCombo(id.c_str(), current.c_str())) {
                for (const std::string& choice : d.choices)
                    if (ImGui::Selectable(choice.c_str(), choice == current) && choice != current) {
                        v = choice;
                        changed = true;
                    }
                ImGui::EndCombo();
            }
            break;
        }
        case PropertyType::String: {
            std::string s = v.get<std::string>();
            if ((changed = ImGui::InputText(id.c_str(), &s, ImGuiInputTextFlags_EnterReturnsTrue)))
                v = s;
            break;
        }
        }
        tooltip(d);
        any = any || changed;
    }
    return any;
}

float minimumWidgetWidth(PropertyType type) {
    const ImGuiStyle& style = ImGui::GetStyle();
    if (type != PropertyType::Color && type != PropertyType::Vec3) return ImGui::GetFontSize() * 6;
    // ColorEdit3 (ImGuiColorEditFlags_Float) shows "R:%0.3f" in each field, DragFloat3 "%.3f";
    // room for values up to 99.999 (HDR colours), the fields' padding and spacing, and the
    // colour's square.
    const char* widest = type == PropertyType::Color ? "R:99.999" : "-99.999";
    const float field = ImGui::CalcTextSize(widest).x + style.FramePadding.x * 2;
    float w = field * 3 + style.ItemInnerSpacing.x * 2;
    if (type == PropertyType::Color) w += style.ItemInnerSpacing.x + ImGui::GetFrameHeight();
    return w;
}

float labelColumnWidth(const std::vector<std::string>& labels) {
    float w = 0.0f;
    for (const std::string& l : labels)
        w = std::max(w, ImGui::CalcTextSize(l.c_str()).x);
    return w;
}

void formLabel(const std::string& label, float width, const std::string& tip, float minWidget) {
    const float x0 = ImGui::GetCursorPosX();
    const float spacing = ImGui::GetStyle().ItemSpacing.x;
    // Too narrow for label and a usable widget side by side: the widget goes below.
    const bool below = ImGui::GetContentRegionAvail().x - width - spacing <
                       std::max(minWidget, ImGui::GetFontSize() * 6);
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted(label.c_str());
    if (!tip.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tip.c_str());
    if (!below) ImGui::SameLine(x0 + width + spacing);
    ImGui::SetNextItemWidth(-FLT_MIN);
}

void jsonTable(const char* id, const nlohmann::json& values) {
    std::vector<std::pair<std::string, std::string>> rows;
    flatten(values, "", rows);
    if (rows.empty()) return;
    if (!ImGui::BeginTable(id, 2,
                           ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_RowBg |
                               ImGuiTableFlags_SizingFixedFit))
        return;
    ImGui::TableSetupColumn("statistic");
    ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch);
    for (const auto& [key, value] : rows) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(key.c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(value.c_str());
    }
    ImGui::EndTable();
}

} // namespace veil::ui
