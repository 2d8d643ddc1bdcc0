// The scene's plain values (render settings, a light's, a camera's, a material's, a grid
// volume's optics), each declared once (src/scene/scene_values.cpp): key, the field it fills,
// the range the parser accepts, the slider range and doc line the viewer shows, and what an
// edit of it in the viewer redoes (EditEffect). The declaration drives
//   - parsing (scene_json.cpp reads every declared key of an object with the range, and the
//     messages, of scene/json_reader.h; the object's accepted keys come from it too),
//   - `--set` (an override is applied to the document, then parsed as above),
//   - the viewer's widgets (value_properties.h turns a group into a PropertySchema),
//   - the report (sceneValues(): the effective values of the declared keys),
//   - the viewer's edits (session::classifyOverride: a live value is copied into the scene
//     that renders, anything else builds a new renderer).
// What is not a plain value (technique choices, names, transforms, paths, a light's aim) and
// the checks between two values (far > near, outer_cone >= inner_cone) stay in the parser.
#pragma once

#include "base/properties.h"
#include "scene/animation.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace veil::scene {

// Which of the viewer's panels edits a value (value_properties.h); None: the parser and the
// report only.
enum class ValueGroup { None, FogMarcher, RenderOutput, Volume, Light, Camera };

// What the viewer redoes when a value is edited (`veil view`, session::ViewSession::set).
enum class EditEffect {
    Rebuild,    // the frame is built from it: a new scene and renderer (the default)
    Live,       // read every frame by per-pixel passes only (exposure, tone map): copied in place
    ShadowMaps, // read every frame, the shadow maps depend on it: copied, the maps redrawn
    Relight,    // a light's or a grid volume's value: copied, the fog's light transmittance
                // volumes recomputed and the shadow maps redrawn
};

// The numbers a key accepts: [lo, hi], an open end excluding its bound (and for vectors,
// every component).
struct AcceptedRange {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool loOpen = false, hiOpen = false;
};

// One declared value of an object of type S (RenderSettings, VolumeRef, Light, Camera,
// Material).
template <class S>
struct ValueDecl {
    using Field = std::variant<int S::*, std::uint32_t S::*, long long S::*, float S::*, bool S::*,
                               glm::vec3 S::*, std::string S::*>;
    PropertyType type = PropertyType::Float; // Vec3 and Color read as 3 numbers
    std::string key;
    Field field;
    AcceptedRange accepted;
    bool scalarAllowed = false; // Color: a single number means grey
    // The viewer's range (within `accepted`: an open end has a closed end inside it).
    double widgetMin = 0.0, widgetMax = 0.0;
    std::vector<std::string> choices; // Enum
    std::string doc, citation;
    ValueGroup group = ValueGroup::None;
    int panelOrder = 0; // the widgets of a group in this order (stable), else as declared
    EditEffect edit = EditEffect::Rebuild;
    // By type index (LightType, CameraType): the documents of which types accept the key, and
    // which types' widgets show it. ~0u: every type.
    unsigned acceptedBy = ~0u, editedFor = ~0u;
    // An integer inside the range that is refused anyway, and the message.
    std::optional<long long> refused;
    std::string refusedMessage;
};

const std::vector<ValueDecl<RenderSettings>>& renderValueDecls();
const std::vector<ValueDecl<VolumeRef>>& volumeValueDecls();
const std::vector<ValueDecl<Light>>& lightValueDecls();
const std::vector<ValueDecl<Camera>>& cameraValueDecls();
const std::vector<ValueDecl<Material>>& materialValueDecls();
// The time block and a sequence volume's values (scene/animation.h).
const std::vector<ValueDecl<TimeSettings>>& timeValueDecls();
const std::vector<ValueDecl<SequenceValues>>& sequenceValueDecls();

inline unsigned typeBit(int typeIndex) { return 1u << unsigned(typeIndex); }

// The declared edit effect of `key` (a key of the object `decls` declares); Rebuild for a key
// not declared there.
template <class S>
EditEffect editEffect(const std::vector<ValueDecl<S>>& decls, const std::string& key) {
    for (const ValueDecl<S>& d : decls)
        if (d.key == key) return d.edit;
    return EditEffect::Rebuild;
}
// A light's aim, "direction" or "target" (parsed apart: not a declared value, it fills
// Light::direction), is edited in place like its position.
inline constexpr EditEffect kLightAimEdit = EditEffect::Relight;

// Copies every value of `from` that the viewer edits in place (edit != Rebuild) into `to`.
template <class S>
void copyLiveValues(const std::vector<ValueDecl<S>>& decls, const S& from, S& to) {
    for (const ValueDecl<S>& d : decls)
        if (d.edit != EditEffect::Rebuild)
            std::visit([&](auto member) { to.*member = from.*member; }, d.field);
}

inline glm::vec3 vec3Of(const nlohmann::json& v) {
    return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
}

// The field's value as JSON (floats as the doubles they are, vectors as arrays).
template <class S>
nlohmann::json valueJson(const ValueDecl<S>& d, const S& s) {
    return std::visit(
        [&](auto member) -> nlohmann::json {
            const auto& v = s.*member;
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, glm::vec3>)
                return nlohmann::json::array({double(v.x), double(v.y), double(v.z)});
            else if constexpr (std::is_same_v<T, float>)
                return double(v);
            else
                return v;
        },
        d.field);
}

// The values of `decls` that the widgets of `group` show for type `typeIndex`, as a schema
// (the viewer's range, doc and citation) and as the {key: value} object the widgets edit.
template <class S>
PropertySchema groupSchema(const std::vector<ValueDecl<S>>& decls, ValueGroup group,
                           int typeIndex = 0) {
    const S defaults{};
    std::vector<const ValueDecl<S>*> shown;
    for (const ValueDecl<S>& d : decls)
        if (d.group == group && (d.editedFor & typeBit(typeIndex))) shown.push_back(&d);
    std::stable_sort(shown.begin(), shown.end(),
                     [](auto* a, auto* b) { return a->panelOrder < b->panelOrder; });
    PropertySchema schema;
    for (const ValueDecl<S>* p : shown) {
        const ValueDecl<S>& d = *p;
        const nlohmann::json def = valueJson(d, defaults);
        switch (d.type) {
        case PropertyType::Bool:
            schema.boolean(d.key, def.get<bool>(), d.doc, d.citation);
            break;
        case PropertyType::Int:
            schema.integer(d.key, def.get<long long>(), (long long)d.widgetMin,
                           (long long)d.widgetMax, d.doc, d.citation);
            break;
        case PropertyType::Float:
            schema.real(d.key, def.get<double>(), d.widgetMin, d.widgetMax, d.doc, d.citation);
            break;
        case PropertyType::Vec3:
            schema.vec3(d.key, vec3Of(def), d.widgetMin, d.widgetMax, d.doc, d.citation);
            break;
        case PropertyType::Color:
            schema.color(d.key, vec3Of(def), d.doc, d.citation);
            break;
        case PropertyType::Enum:
            schema.choice(d.key, def.get<std::string>(), d.choices, d.doc, d.citation);
            break;
        case PropertyType::String:
            schema.text(d.key, def.get<std::string>(), d.doc, d.citation);
            break;
        }
    }
    return schema;
}

template <class S>
nlohmann::json groupValues(const std::vector<ValueDecl<S>>& decls, ValueGroup group, const S& s,
                           int typeIndex = 0) {
    nlohmann::json out = nlohmann::json::object();
    for (const ValueDecl<S>& d : decls)
        if (d.group == group && (d.editedFor & typeBit(typeIndex))) out[d.key] = valueJson(d, s);
    return out;
}

// Every declared value of the scene as {render: {...}, cameras: [...], lights: [...],
// materials: {name: {...}}, volumes: [...]} (the keys each object's document accepts), for
// the report.
nlohmann::json sceneValues(const Scene& scene);

} // namespace veil::scene
