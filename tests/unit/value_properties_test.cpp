// The declared properties of the scene values the viewer edits (scene/value_properties.h)
// agree with the scene parser, which they do not share code with: each schema's default is
// what a scene without the key parses to, every declared key set to its range's ends (and
// to a middle value) in a document parses to that value, read back through the values()
// functions the widgets edit.
#include "scene/scene.h"
#include "scene/value_properties.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <functional>

using nlohmann::json;
using namespace veil;
using namespace veil::scene;

namespace {

// A document with one spot, point and directional light, a perspective and an orthographic
// camera and a grid volume.
json document() {
    return json::parse(R"({
      "cameras": [{"name": "p"}, {"name": "o", "type": "orthographic"}],
      "lights": [{"type": "spot"}, {"type": "point"}, {"type": "directional"}],
      "volumes": [{"procedural": "sphere", "size": 1, "voxel_size": 0.25}]
    })");
}

// Values to try for a declaration: its ends (where finite) and a value inside.
std::vector<json> samples(const PropertyDecl& d) {
    switch (d.type) {
    case PropertyType::Bool:
        return {true, false};
    case PropertyType::Int:
        return {static_cast<long long>(d.min), static_cast<long long>(d.max), 2};
    case PropertyType::Float:
        return {d.min, d.max, d.min + (d.max - d.min) * 0.25};
    case PropertyType::Color:
        return {json::array({0.0, 0.5, 1.0}), json::array({0.25, 0.25, 0.25})};
    case PropertyType::Vec3:
        return {json::array({d.min, 0.0, d.max}), json::array({1.5, -2.0, 3.0})};
    case PropertyType::Enum:
        return {d.choices.begin(), d.choices.end()};
    default:
        return {};
    }
}

bool sameValue(const json& a, const json& b) {
    if (a.is_number() && b.is_number()) // the scene keeps floats
        return static_cast<float>(a.get<double>()) == static_cast<float>(b.get<double>());
    if (a.is_array() && b.is_array() && a.size() == b.size()) {
        for (std::size_t i = 0; i < a.size(); ++i)
            if (!sameValue(a[i], b[i])) return false;
        return true;
    }
    return a == b;
}

// For each key of `schema`: the parsed default, then each sample written at `path` + key.
void check(const PropertySchema& schema, const json::json_pointer& path,
           const std::function<json(const Scene&)>& values) {
    const json defaults = values(parseScene(document(), "."));
    for (const PropertyDecl& d : schema.all()) {
        SCOPED_TRACE(path.to_string() + "/" + d.key);
        EXPECT_TRUE(sameValue(defaults.at(d.key), d.defaultValue))
            << "parsed " << defaults.at(d.key) << ", declared " << d.defaultValue;
        for (const json& v : samples(d)) {
            json doc = document();
            doc[path / d.key] = v;
            if (d.key == "inner_cone") doc[path / "outer_cone"] = 90.0; // outer >= inner
            if (d.key == "outer_cone") doc[path / "inner_cone"] = 0.0;
            if (d.key == "near") doc[path / "far"] = 1e7;
            if (d.key == "far") doc[path / "near"] = 1e-5;
            if (d.key == "fog_resolution" && v == 3) continue; // refused, as the doc says
            json got;
            ASSERT_NO_THROW(got = values(parseScene(doc, "."))) << "value " << v;
            EXPECT_TRUE(sameValue(got.at(d.key), v)) << "set " << v << ", parsed " << got[d.key];
        }
    }
}

} // namespace

TEST(ValuePropertiesTest, DeclaredKeysRangesAndDefaultsMatchTheParser) {
    check(fogMarcherProperties(), json::json_pointer("/render"),
          [](const Scene& s) { return fogMarcherValues(s.render); });
    check(renderOutputProperties(), json::json_pointer("/render"),
          [](const Scene& s) { return renderOutputValues(s.render); });
    check(volumeProperties(), json::json_pointer("/volumes/0"),
          [](const Scene& s) { return volumeValues(s.volumes[0]); });
    const LightType types[] = {LightType::Spot, LightType::Point, LightType::Directional};
    for (int i = 0; i < 3; ++i)
        check(lightProperties(types[i]), json::json_pointer("/lights/" + std::to_string(i)),
              [i](const Scene& s) { return lightValues(s.lights[i]); });
    check(cameraProperties(CameraType::Perspective), json::json_pointer("/cameras/0"),
          [](const Scene& s) { return cameraValues(s.cameras[0]); });
    check(cameraProperties(CameraType::Orthographic), json::json_pointer("/cameras/1"),
          [](const Scene& s) { return cameraValues(s.cameras[1]); });
}

TEST(ValuePropertiesTest, EveryDeclarationHasADocLine) {
    for (const PropertySchema* s :
         {&fogMarcherProperties(), &renderOutputProperties(), &volumeProperties(),
          &lightProperties(LightType::Spot), &cameraProperties(CameraType::Perspective),
          &cameraProperties(CameraType::Orthographic)})
        for (const PropertyDecl& d : s->all())
            EXPECT_FALSE(d.doc.empty()) << d.key;
}
