#include "ui/property_widgets.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace veil::ui {

namespace {

void tooltip(const PropertyDecl& d) {
    if (!ImGui::IsItemHovered()) return;
    std::string text = d.doc;
    if (!d.citation.empty()) text += "\n" + d.citation;
    if (const std::string range = d.rangeText(); !range.empty()) text += "\nrange " + range;
    ImGui::SetTooltip("%s", text.c_str());
}

// Drag speed for a float: a hundredth of the value's magnitude (or of the range).
float speedFor(double value, const PropertyDecl& d) {
    double scale = std::fabs(value);
    if (std::isfinite(d.max) && std::isfinite(d.min))
        scale = std::max(scale, (d.max - d.min) / 100.0);
    return static_cast<float>(std::max(scale * 0.01, 1e-7));
}

bool floatWidget(const PropertyDecl& d, nlohmann::json& v) {
    double x = v.get<double>();
    const double lo = std::isfinite(d.min) ? d.min : -1e30,
                 hi = std::isfinite(d.max) ? d.max : 1e30;
    const bool changed = ImGui::DragScalar(d.key.c_str(), ImGuiDataType_Double, &x, speedFor(x, d),
                                           &lo, &hi, "%.6g", ImGuiSliderFlags_AlwaysClamp);
    if (changed) v = std::clamp(x, lo, hi);
    return changed;
}

} // namespace

bool propertyWidgets(const PropertySchema& schema, nlohmann::json& values) {
    bool any = false;
    for (const PropertyDecl& d : schema.all()) {
        nlohmann::json& v = values[d.key];
        if (v.is_null()) v = d.defaultValue;
        bool changed = false;
        switch (d.type) {
        case PropertyType::Bool: {
            bool b = v.get<bool>();
            if ((changed = ImGui::Checkbox(d.key.c_str(), &b))) v = b;
            break;
        }
        case PropertyType::Int: {
            int i = static_cast<int>(v.get<long long>());
            const int lo = static_cast<int>(std::max(d.min, -1e9));
            const int hi = static_cast<int>(std::min(d.max, 1e9));
            changed = hi - lo <= 256 ? ImGui::SliderInt(d.key.c_str(), &i, lo, hi)
                                     : ImGui::DragInt(d.key.c_str(), &i, 1.0f, lo, hi);
            if (changed) v = std::clamp(i, lo, hi);
            break;
        }
        case PropertyType::Float:
            changed = floatWidget(d, v);
            break;
        case PropertyType::Vec3:
        case PropertyType::Color: {
            float c[3] = {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
            changed = d.type == PropertyType::Color
                          ? ImGui::ColorEdit3(d.key.c_str(), c,
                                              ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR)
                          : ImGui::DragFloat3(d.key.c_str(), c, 0.01f);
            if (changed)
                for (int k = 0; k < 3; ++k)
                    v[k] = std::clamp(static_cast<double>(c[k]), d.min, d.max);
            break;
        }
        case PropertyType::Enum: {
            const std::string current = v.get<std::string>();
            if (ImGui::BeginCombo(d.key.c_str(), current.c_str())) {
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
            if ((changed =
                     ImGui::InputText(d.key.c_str(), &s, ImGuiInputTextFlags_EnterReturnsTrue)))
                v = s;
            break;
        }
        }
        tooltip(d);
        any = any || changed;
    }
    return any;
}

} // namespace veil::ui
