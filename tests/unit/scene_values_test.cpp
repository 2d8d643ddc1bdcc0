// The scene values' one declaration (src/scene/scene_values.cpp) and what it drives: the keys
// an object accepts (in the order the unknown-key message lists them), `--set` through the
// document, the refused value's message, the report's scene_values, and declarations whose
// viewer ranges lie inside what the parser accepts.
#include "base/error.h"
#include "scene/scene.h"
#include "scene/scene_values.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

using nlohmann::json;
using namespace veil;
using namespace veil::scene;

namespace {

json document() {
    return json::parse(R"({
      "cameras": [{"name": "p"}, {"name": "o", "type": "orthographic"}],
      "lights": [{"type": "spot"}, {"type": "point"}, {"type": "directional"}],
      "volumes": [{"procedural": "sphere", "size": 1, "voxel_size": 0.25}],
      "materials": {"glass": {}}
    })");
}

std::string parseError(const json& doc) {
    try {
        parseScene(doc, ".");
    } catch (const Error& e) {
        return e.what();
    }
    return "(parsed)";
}

template <class S>
void expectWidgetRangesAccepted(const std::vector<ValueDecl<S>>& decls) {
    for (const ValueDecl<S>& d : decls) {
        SCOPED_TRACE(d.key);
        EXPECT_FALSE(d.doc.empty());
        if (d.group == ValueGroup::None) continue;
        if (d.type != PropertyType::Int && d.type != PropertyType::Float &&
            d.type != PropertyType::Vec3)
            continue;
        const AcceptedRange& a = d.accepted;
        EXPECT_TRUE(a.loOpen ? d.widgetMin > a.lo : d.widgetMin >= a.lo) << d.widgetMin;
        EXPECT_TRUE(a.hiOpen ? d.widgetMax < a.hi : d.widgetMax <= a.hi) << d.widgetMax;
        EXPECT_LE(d.widgetMin, d.widgetMax);
    }
}

} // namespace

TEST(SceneValuesTest, UnknownKeyListsTheAcceptedKeysInOrder) {
    json doc = document();
    doc["render"]["fog_stepz"] = 3;
    EXPECT_NE(parseError(doc).find(
                  "/render/fog_stepz: unknown key (did you mean 'fog_steps'?) (known: width, "
                  "height, camera, oit, shadows, ao, "
                  "pathtraced, "
                  "seed, ambient, background, exposure, oit_rasterizer, tonemap, shadow_map_size, "
                  "shadow_bias, pcf_radius, fog_steps, fog_resolution, fog_jitter, fog_octaves, "
                  "fog_octave_extinction, fog_octave_scattering, fog_octave_anisotropy, "
                  "fog_octave_radius, "
                  "fog_scattered_light, fog_scattered_light_samples, "
                  "fog_scattered_light_surface_factor, fog_scattered_light_cell, "
                  "fog_scattered_light_bake, fog_scattered_light_budget_ms, "
                  "fog_scattered_light_frame_ms, "
                  "fog_ambient, volume_budget_mib, sequence_gpu_cache_mib, "
                  "volume_over_budget, geometry_budget_mib, fog_sample_limit)"),
              std::string::npos)
        << parseError(doc);
    doc = document();
    doc["lights"][0]["cone"] = 3;
    EXPECT_NE(parseError(doc).find("/lights/0/cone: unknown key (known: name, type, color, "
                                   "intensity, shadows, position, direction, target, "
                                   "inner_cone, outer_cone, keys, interpolation)"),
              std::string::npos)
        << parseError(doc);
    doc = document();
    doc["lights"][1]["direction"] = json::array({0, -1, 0}); // a point light has no aim
    EXPECT_NE(parseError(doc).find("/lights/1/direction: unknown key (known: name, type, color, "
                                   "intensity, shadows, position, keys, interpolation)"),
              std::string::npos)
        << parseError(doc);
    doc = document();
    doc["cameras"][1]["fov_y"] = 30;
    EXPECT_NE(parseError(doc).find("/cameras/1/fov_y: unknown key (known: name, type, position, "
                                   "target, up, near, far, ortho_height, keys, interpolation, "
                                   "turntable)"),
              std::string::npos)
        << parseError(doc);
    doc = document();
    doc["volumes"][0]["albedo"] = 1.5;
    EXPECT_NE(parseError(doc).find("/volumes/0/albedo: value 1.5 out of range [0, 1]"),
              std::string::npos)
        << parseError(doc);
}

TEST(SceneValuesTest, RefusedValueAndRangesKeepTheirMessages) {
    json doc = document();
    doc["render"]["fog_resolution"] = 3;
    EXPECT_NE(parseError(doc).find("/render/fog_resolution: must be 1, 2 or 4"), std::string::npos)
        << parseError(doc);
    doc["render"]["fog_resolution"] = 5;
    EXPECT_NE(parseError(doc).find("/render/fog_resolution: value 5 out of range [1, 4]"),
              std::string::npos)
        << parseError(doc);
    doc = document();
    doc["render"]["exposure"] = 0;
    EXPECT_NE(parseError(doc).find("/render/exposure: value 0 out of range (0, inf]"),
              std::string::npos)
        << parseError(doc);
}

TEST(SceneValuesTest, SetReachesTheReportedValues) {
    json doc = document();
    applyOverrides(doc, {"render.fog_steps=7", "render.tonemap=clamp", "lights.0.inner_cone=5",
                         "cameras.1.ortho_height=3", "volumes.0.albedo=0.5",
                         "render.fog_sample_limit=0", "materials.glass.alpha=0.25"});
    const json v = sceneValues(parseScene(doc, "."));
    EXPECT_EQ(v["render"]["fog_steps"], 7);
    EXPECT_EQ(v["render"]["tonemap"], "clamp");
    EXPECT_EQ(v["render"]["fog_sample_limit"], 0);
    EXPECT_EQ(v["render"]["width"], RenderSettings{}.width);
    EXPECT_EQ(v["lights"][0]["inner_cone"], 5.0);
    EXPECT_FALSE(v["lights"][1].contains("inner_cone")); // a point light has no cone
    EXPECT_EQ(v["cameras"][1]["ortho_height"], 3.0);
    EXPECT_FALSE(v["cameras"][1].contains("fov_y"));
    EXPECT_EQ(v["volumes"][0]["albedo"], json::array({0.5, 0.5, 0.5}));
    EXPECT_EQ(v["materials"]["glass"]["alpha"], 0.25);
    EXPECT_EQ(v["materials"]["glass"]["ior"], 1.5);
}

TEST(SceneValuesTest, ViewerRangesLieInsideTheAcceptedRanges) {
    expectWidgetRangesAccepted(renderValueDecls());
    expectWidgetRangesAccepted(volumeValueDecls());
    expectWidgetRangesAccepted(lightValueDecls());
    expectWidgetRangesAccepted(cameraValueDecls());
    expectWidgetRangesAccepted(materialValueDecls());
}

TEST(SceneValuesTest, EmissionGridsNeedAFileAndExcludeEachOther) {
    json doc = document();
    doc["volumes"][0]["temperature_grid"] = "temperature";
    EXPECT_NE(parseError(doc).find("/volumes/0/temperature_grid: a procedural volume has no file"),
              std::string::npos)
        << parseError(doc);
    doc = document();
    doc["volumes"][0] = {
        {"path", std::string(VEIL_DATA_DIR) + "/vdb-embergen-fire-seq/embergen_fire_a_1.vdb"},
        {"grid", "flames"},
        {"temperature_grid", "temperature"},
        {"temperature_scale", 1000},
        {"temperature_offset", 1000},
        {"temperature_intensity", 0.5}};
    const Scene s = parseScene(doc, ".");
    EXPECT_EQ(s.volumes[0].temperatureGrid, "temperature");
    EXPECT_FLOAT_EQ(s.volumes[0].temperatureScale, 1000.0f);
    EXPECT_FLOAT_EQ(s.volumes[0].temperatureOffset, 1000.0f);
    EXPECT_FLOAT_EQ(s.volumes[0].temperatureIntensity, 0.5f);
    doc["volumes"][0]["emission_grid"] = "flames";
    EXPECT_NE(parseError(doc).find(
                  "/volumes/0/temperature_grid: give either emission_grid or temperature_grid"),
              std::string::npos)
        << parseError(doc);
    doc["volumes"][0].erase("emission_grid");
    doc["volumes"][0]["temperature_intensity"] = -1;
    EXPECT_NE(parseError(doc).find("/volumes/0/temperature_intensity: value -1 out of range"),
              std::string::npos)
        << parseError(doc);
}
