// The JSON scene format: defaults, every shape, error messages naming the file and JSON
// pointer, overrides, transform order, camera projection and mesh files in scenes.
#include "base/error.h"
#include "scene/scene.h"
#include "support/test_support.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using nlohmann::json;
using namespace veil::scene;
using veil::test::errorOf;

namespace {

const fs::path kThirdParty = VEIL_DATA_DIR;

fs::path outputDir() { return veil::test::outputSubdir("scene_test"); }

fs::path writeScene(const std::string& name, const std::string& text) {
    fs::path path = outputDir() / name;
    std::ofstream(path) << text;
    return path;
}

// A minimal valid document to which each test adds what it needs.
json minimal() { return json::parse(R"({"cameras": [{"name": "main"}]})"); }

std::string parseError(const json& doc) {
    return errorOf([&] { parseScene(doc, kThirdParty); });
}

void expectContains(const std::string& message, const std::vector<std::string>& parts) {
    EXPECT_FALSE(message.empty()) << "expected an error";
    for (const std::string& p : parts)
        EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

} // namespace

TEST(SceneTest, MinimalSceneHasDefaults) {
    Scene s = parseScene(minimal(), ".");
    EXPECT_EQ(s.render.width, 640);
    EXPECT_EQ(s.render.height, 360);
    EXPECT_EQ(s.render.oit, "blend");
    EXPECT_EQ(s.render.tonemap, "aces");
    EXPECT_EQ(s.render.shadows, "opaque");
    EXPECT_TRUE(s.render.shadowProperties.is_null()); // the technique's defaults
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.cameras[0].type, CameraType::Perspective);
    EXPECT_FLOAT_EQ(s.cameras[0].fovYDegrees, 45.0f);
    EXPECT_EQ(&s.camera(), &s.cameras[0]);
    EXPECT_EQ(&s.camera("main"), &s.cameras[0]);
    EXPECT_THROW(s.camera("other"), veil::Error);
    EXPECT_TRUE(s.objects.empty());
    EXPECT_TRUE(s.lights.empty());
}

TEST(SceneTest, FullRenderAndLightSettings) {
    json doc = json::parse(R"({
      "render": {"width": 320, "height": 200, "camera": "top", "oit": "moment-p6", "seed": 42,
                 "ambient": 0.1, "background": [0.1, 0.2, 0.3], "exposure": 2, "tonemap": "clamp",
                 "shadow_map_size": 1024, "shadow_bias": 0.002, "pcf_radius": 2},
      "cameras": [{"name": "main"},
                  {"name": "top", "type": "orthographic", "position": [0, 10, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 4}],
      "lights": [{"type": "spot", "position": [0, 4, 0], "target": [0, 0, 3], "inner_cone": 10,
                  "outer_cone": 15, "intensity": 3, "shadows": false},
                 {"type": "directional", "direction": [0, -2, 0]},
                 {"type": "point", "position": [1, 2, 3], "color": [1, 0.5, 0]}]
    })");
    Scene s = parseScene(doc, ".");
    EXPECT_EQ(s.render.seed, 42u);
    EXPECT_EQ(s.render.ambient, glm::vec3(0.1f));
    EXPECT_EQ(s.camera().name, "top"); // render.camera picks the default camera
    EXPECT_EQ(s.camera().type, CameraType::Orthographic);
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].type, LightType::Spot);
    EXPECT_NEAR(glm::length(s.lights[0].direction - glm::vec3(0.0f, -0.8f, 0.6f)), 0.0f, 1e-6f);
    EXPECT_FALSE(s.lights[0].castShadows);
    EXPECT_EQ(s.lights[1].direction, glm::vec3(0.0f, -1.0f, 0.0f)); // normalized
    EXPECT_EQ(s.lights[2].type, LightType::Point);
    // The legacy shadow keys are aliases of the shadow technique's properties.
    EXPECT_EQ(s.render.shadowProperties,
              json({{"size", 1024}, {"bias", 0.002}, {"pcf_radius", 2}}));
}

TEST(SceneTest, ShadowTechniqueChoice) {
    json doc = minimal();
    doc["render"] = json::parse(R"({"shadows": {"type": "moment", "size": 512}})");
    Scene s = parseScene(doc, ".");
    EXPECT_EQ(s.render.shadows, "moment");
    EXPECT_EQ(s.render.shadowProperties, json({{"size", 512}}));
    EXPECT_NE(s.render.shadowsWhere.find("/render/shadows"), std::string::npos);
    doc["render"] = json::parse(R"({"shadows": "opaque"})");
    EXPECT_EQ(parseScene(doc, ".").render.shadows, "opaque");
    // A legacy key and its property both set: which one wins is not guessed.
    doc["render"] =
        json::parse(R"({"shadows": {"type": "opaque", "size": 512}, "shadow_map_size": 64})");
    EXPECT_THROW(parseScene(doc, "."), veil::Error);
    // No type: the default technique with these properties.
    doc["render"] = json::parse(R"({"shadows": {"size": 512}})");
    EXPECT_EQ(parseScene(doc, ".").render.shadows, "opaque");
    doc["render"] = json::parse(R"({"shadows": {"type": 3}})");
    EXPECT_THROW(parseScene(doc, "."), veil::Error);
}

TEST(SceneTest, EveryShapeKind) {
    json doc = minimal();
    doc["materials"] = json::parse(R"({"m": {}})");
    doc["objects"] = json::parse(R"([
      {"shape": {"type": "plane", "size": [2, 3], "subdivisions": 2}, "material": "m"},
      {"shape": {"type": "box", "size": 2}, "material": "m"},
      {"shape": {"type": "sphere", "radius": 0.5, "segments": 8, "rings": 4}, "material": "m"},
      {"shape": {"type": "torus", "major_radius": 1, "minor_radius": 0.2}, "material": "m"},
      {"shape": {"type": "particles", "count": 10, "radius": 1, "particle_size": 0.1, "seed": 3},
       "material": "m", "shadows": false}
    ])");
    Scene s = parseScene(doc, ".");
    ASSERT_EQ(s.objects.size(), 5u);
    ASSERT_EQ(s.meshes.size(), 5u);
    EXPECT_EQ(s.meshes[s.objects[0].mesh].triangleCount(), 8u);
    EXPECT_EQ(s.meshes[s.objects[1].mesh].triangleCount(), 12u);
    EXPECT_EQ(s.meshes[s.objects[2].mesh].triangleCount(), 2u * 8u * 4u - 2u * 8u);
    EXPECT_EQ(s.meshes[s.objects[3].mesh].triangleCount(), 2u * 48u * 24u);
    EXPECT_TRUE(s.meshes[s.objects[4].mesh].billboard);
    EXPECT_EQ(s.meshes[s.objects[4].mesh].positions.size(), 40u);
    EXPECT_FALSE(s.objects[4].castShadows);
    EXPECT_EQ(s.objects[2].name, "object2");
    glm::vec3 lo, hi;
    s.bounds(lo, hi);
    EXPECT_NEAR(hi.x, 1.2f, 1e-5f); // the torus's outer radius, beyond the box (1) and plane (1)
    EXPECT_NEAR(hi.z, 1.5f, 1e-5f); // the plane's half-depth
}

TEST(SceneTest, UnknownKeyNamesTheNestedPath) {
    json doc = minimal();
    doc["materials"] = {{"m", json::object()}};
    doc["objects"] = json::parse(R"([
      {"shape": {"type": "box"}, "material": "m"}, {"shape": {"type": "box"}, "material": "m"},
      {"shape": {"type": "sphere", "radiuss": 2}, "material": "m"}])");
    expectContains(parseError(doc),
                   {"/objects/2/shape/radiuss", "unknown key", "radius", "segments"});

    json top = minimal();
    top["renderr"] = json::object();
    expectContains(parseError(top), {"/renderr", "unknown key", "render"});
}

TEST(SceneTest, WrongTypeNamesThePathAndValue) {
    json doc = minimal();
    doc["render"] = {{"width", "wide"}};
    expectContains(parseError(doc), {"/render/width", "expected an integer", "\"wide\""});

    json cam = minimal();
    cam["cameras"][0]["position"] = {1, 2};
    expectContains(parseError(cam), {"/cameras/0/position", "array of 3 numbers"});

    json shadows = minimal();
    shadows["lights"] = json::parse(R"([{"shadows": "yes"}])");
    expectContains(parseError(shadows), {"/lights/0/shadows", "true or false"});
}

TEST(SceneTest, OutOfRangeValuesAreErrors) {
    struct Case {
        std::string patch, pointer, value;
    };
    const std::vector<Case> cases = {
        {R"({"render": {"width": 0}})", "/render/width", "0"},
        {R"({"render": {"height": 20000}})", "/render/height", "20000"},
        {R"({"materials": {"glass": {"roughness": 1.5}}})", "/materials/glass/roughness", "1.5"},
        {R"({"materials": {"glass": {"ior": 0.9}}})", "/materials/glass/ior", "0.9"},
        {R"({"materials": {"glass": {"transmission": [0.5, 1.2, 0]}}})",
         "/materials/glass/transmission/1", "1.2"},
        {R"({"materials": {"glass": {"base_color": -1}}})", "/materials/glass/base_color", "-1"},
        {R"({"cameras": [{"fov_y": 180}]})", "/cameras/0/fov_y", "180"},
        {R"({"cameras": [{"near": 2, "far": 1}]})", "/cameras/0/far", "near"},
        {R"({"cameras": [{"position": [1, 1, 1], "target": [1, 1, 1]}]})", "/cameras/0/target",
         "position"},
        {R"({"lights": [{"type": "spot", "inner_cone": 40, "outer_cone": 30}]})",
         "/lights/0/outer_cone", "inner_cone"},
        {R"({"lights": [{"intensity": -1}]})", "/lights/0/intensity", "-1"},
        {R"({"lights": [{"type": "point", "direction": [0, 1, 0]}]})", "/lights/0/direction",
         "unknown key"},
        {R"({"render": {"tonemap": "filmic"}})", "/render/tonemap", "filmic"},
        {R"({"render": {"camera": "nope"}})", "/render/camera", "nope"},
    };
    for (const Case& c : cases) {
        json doc = minimal();
        doc.merge_patch(json::parse(c.patch));
        expectContains(parseError(doc), {c.pointer, c.value});
    }
}

TEST(SceneTest, NaNAndMissingCameraAreErrors) {
    json doc = minimal();
    doc["render"] = {{"exposure", std::numeric_limits<double>::quiet_NaN()}};
    expectContains(parseError(doc), {"/render/exposure", "finite"});
    expectContains(parseError(json::object()), {"/cameras", "at least one camera"});
    expectContains(parseError(json::parse(R"({"cameras": []})")), {"at least one camera"});
}

TEST(SceneTest, UnknownMaterialAndMissingShapeMaterial) {
    json doc = minimal();
    doc["materials"] = {{"glass", json::object()}};
    doc["objects"] = json::parse(R"([{"shape": {"type": "box"}, "material": "nope"}])");
    expectContains(parseError(doc), {"/objects/0/material", "unknown material 'nope'", "glass"});

    doc["objects"] = json::parse(R"([{"shape": {"type": "box"}}])");
    expectContains(parseError(doc), {"/objects/0", "material"});

    doc["objects"] = json::parse(R"([{"material": "glass"}])");
    expectContains(parseError(doc), {"/objects/0", "exactly one of 'shape' and 'mesh'"});
}

TEST(SceneTest, MissingMeshFileNamesPathAndPointer) {
    json doc = minimal();
    doc["objects"] = json::parse(R"([{"mesh": "no/such/model.glb"}])");
    expectContains(parseError(doc), {"/objects/0/mesh", "no/such/model.glb", "does not exist"});
    // A directory or a device is not "missing": say what it is.
    doc["objects"] = json::parse(R"([{"mesh": "/dev/null"}])");
    expectContains(parseError(doc), {"/objects/0/mesh", "/dev/null", "is not a regular file"});
    doc["objects"] = json::parse(R"([{"mesh": "/tmp"}])");
    expectContains(parseError(doc), {"/objects/0/mesh", "is not a regular file"});
}

TEST(SceneTest, MalformedJsonNamesTheFile) {
    fs::path path =
        writeScene("truncated.json", R"({"cameras": [{"name": "main"}], "render": {"wid)");
    std::string message = errorOf([&] { loadScene(path); });
    expectContains(message, {path.string(), "parse error", "line 1"});

    std::string missing = errorOf([&] { loadScene(outputDir() / "absent.json"); });
    expectContains(missing, {"cannot open scene file", "absent.json"});
}

TEST(SceneTest, ErrorsFromFilesCarryTheFileName) {
    fs::path path = writeScene("bad_value.json", R"({"cameras": [{"fov_y": -5}]})");
    std::string message = errorOf([&] { loadScene(path); });
    expectContains(message, {path.string() + ": /cameras/0/fov_y: ", "-5"});
}

TEST(SceneTest, OverridesSetValuesIndexArraysAndRejectBadSyntax) {
    json doc = minimal();
    doc["lights"] = json::parse(R"([{"intensity": 1}, {"intensity": 2}])");
    doc["materials"] = json::parse(R"({"glass": {"alpha": 1}})");
    applyOverrides(doc, {"render.width=320", "lights.1.intensity=5", "materials.glass.alpha=0.5",
                         "render.tonemap=clamp", "cameras.0.position=[1,2,3]"});
    EXPECT_EQ(doc["render"]["width"], 320);
    EXPECT_TRUE(doc["render"]["width"].is_number_integer());
    EXPECT_EQ(doc["lights"][1]["intensity"], 5);
    EXPECT_EQ(doc["lights"][0]["intensity"], 1);
    EXPECT_EQ(doc["materials"]["glass"]["alpha"], 0.5);
    EXPECT_EQ(doc["render"]["tonemap"], "clamp"); // not JSON, so a string
    Scene s = parseScene(doc, ".");
    EXPECT_EQ(s.render.width, 320);
    EXPECT_EQ(s.cameras[0].position, glm::vec3(1, 2, 3));

    EXPECT_THROW(applyOverrides(doc, {"render.width"}), veil::Error);
    EXPECT_THROW(applyOverrides(doc, {"=5"}), veil::Error);
    expectContains(errorOf([&] { applyOverrides(doc, {"lights.7.intensity=1"}); }),
                   {"lights.7.intensity", "out of range"});
    expectContains(errorOf([&] { applyOverrides(doc, {"lights.x=1"}); }), {"not an index"});
    expectContains(errorOf([&] { applyOverrides(doc, {"render.width.x=1"}); }), {"render.width"});
}

TEST(SceneTest, LoadSceneAppliesOverridesBeforeValidation) {
    fs::path path = writeScene("override.json", R"({
      // comments are allowed
      "render": {"width": 0},
      "cameras": [{"name": "main"}]})");
    EXPECT_THROW(loadScene(path), veil::Error);
    Scene s = loadScene(path, {"render.width=100"});
    EXPECT_EQ(s.render.width, 100);
    EXPECT_EQ(s.sourcePath, fs::absolute(path));
}

TEST(SceneTest, TransformAppliesScaleThenXThenYThenZThenTranslate) {
    json doc = minimal();
    doc["materials"] = {{"m", json::object()}};
    doc["objects"] = json::parse(R"([
      {"shape": {"type": "box"}, "material": "m",
       "transform": {"translate": [1, 2, 3], "rotate": [90, 90, 0], "scale": 2}},
      {"shape": {"type": "box"}, "material": "m",
       "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 4,5,6,1]}}])");
    Scene s = parseScene(doc, ".");
    // (0,1,0) -> scale (0,2,0) -> Rx90 (0,0,2) -> Ry90 (2,0,0) -> translate (3,2,3).
    // The opposite rotation order would give (1,2,5).
    glm::vec3 p = glm::vec3(s.objects[0].transform * glm::vec4(0, 1, 0, 1));
    EXPECT_NEAR(glm::length(p - glm::vec3(3, 2, 3)), 0.0f, 1e-5f)
        << p.x << " " << p.y << " " << p.z;
    glm::vec3 q = glm::vec3(s.objects[1].transform * glm::vec4(1, 1, 1, 1));
    EXPECT_EQ(q, glm::vec3(5, 6, 7)); // column-major: elements 12..14 are the translation

    doc["objects"][1]["transform"]["scale"] = 2;
    expectContains(parseError(doc), {"/objects/1/transform", "matrix"});
}

TEST(SceneTest, PerspectiveProjectionOfThePointOnTheViewAxis) {
    Camera cam;
    cam.position = {1, 2, 3};
    cam.target = {1, 2, -10};
    cam.fovYDegrees = 60.0f;
    cam.nearPlane = 0.1f;
    cam.farPlane = 50.0f;
    const float aspect = 16.0f / 9.0f;
    const glm::mat4 vp = cam.projection(aspect) * cam.view();
    const double n = 0.1, f = 50.0;
    for (double d : {0.1, 1.0, 7.5, 50.0}) {
        glm::vec4 clip = vp * glm::vec4(1.0f, 2.0f, float(3.0 - d), 1.0f);
        glm::vec3 ndc = glm::vec3(clip) / clip.w;
        double expected = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * d);
        EXPECT_NEAR(ndc.x, 0.0, 1e-6);
        EXPECT_NEAR(ndc.y, 0.0, 1e-6);
        EXPECT_NEAR(ndc.z, expected, 1e-4) << "d = " << d;
    }
    // A point at the top edge of the field of view maps to ndc y = 1.
    const double d = 4.0;
    glm::vec4 top =
        vp * glm::vec4(1.0f, float(2.0 + d * std::tan(glm::radians(30.0))), float(3.0 - d), 1.0f);
    EXPECT_NEAR(top.y / top.w, 1.0, 1e-5);
}

TEST(SceneTest, OrthographicProjectionIsLinearInDepth) {
    Camera cam;
    cam.type = CameraType::Orthographic;
    cam.position = {0, 0, 0};
    cam.target = {0, 0, -1};
    cam.orthoHeight = 4.0f;
    cam.nearPlane = 1.0f;
    cam.farPlane = 11.0f;
    const glm::mat4 vp = cam.projection(2.0f) * cam.view();
    glm::vec4 p = vp * glm::vec4(4.0f, 2.0f, -6.0f, 1.0f); // corner of the view volume
    EXPECT_NEAR(p.x / p.w, 1.0, 1e-6);
    EXPECT_NEAR(p.y / p.w, 1.0, 1e-6);
    EXPECT_NEAR(p.z / p.w, (2.0 * 6.0 - 12.0) / 10.0, 1e-6);
}

TEST(SceneTest, MaterialTransparency) {
    Material m;
    EXPECT_FALSE(m.isTransparent());
    m.alpha = 0.99f;
    EXPECT_TRUE(m.isTransparent());
    m.alpha = 1.0f;
    m.transmission = {0.0f, 0.0f, 0.1f};
    EXPECT_TRUE(m.isTransparent());

    json doc = minimal();
    doc["materials"] =
        json::parse(R"({"glass": {"transmission": 0.9, "ior": 1.5, "collimation": 0.5}})");
    Scene s = parseScene(doc, ".");
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "glass");
    EXPECT_EQ(s.materials[0].transmission, glm::vec3(0.9f));
    EXPECT_TRUE(s.materials[0].isTransparent());
}

TEST(SceneTest, MeshFilesBringTheirMaterials) {
    json doc = minimal();
    doc["materials"] = {{"red", {{"base_color", {1, 0, 0}}}}};
    doc["objects"] = json::parse(R"([
      {"name": "vase", "mesh": "gltf-GlassVaseFlowers/GlassVaseFlowers.glb"},
      {"name": "vase2", "mesh": "gltf-GlassVaseFlowers/GlassVaseFlowers.glb", "material": "red",
       "transform": {"translate": [2, 0, 0]}},
      {"name": "teapot", "mesh": "utah-teapot/teapot.obj", "shadows": false}])");
    Scene s = parseScene(doc, kThirdParty);
    ASSERT_EQ(s.objects.size(), 7u); // 3 + 3 + 1
    EXPECT_EQ(s.meshes.size(), 4u);  // the vase file is loaded once
    const Material* glassAlpha = nullptr;
    const Material* glassTransmission = nullptr;
    for (const Material& m : s.materials) {
        if (m.name == "GlassVaseFlowers/GlassAlpha") glassAlpha = &m;
        if (m.name == "GlassVaseFlowers/GlassTransmission") glassTransmission = &m;
    }
    ASSERT_NE(glassAlpha, nullptr);
    ASSERT_NE(glassTransmission, nullptr);
    EXPECT_NEAR(glassAlpha->alpha, 0.3f, 1e-4f);
    EXPECT_GT(glassTransmission->transmission.y, 0.0f);
    for (int i = 3; i < 6; ++i)
        EXPECT_EQ(s.materials[s.objects[i].material].name, "red");
    EXPECT_NE(s.objects[0].name.find("vase/"), std::string::npos);
    const Object& teapot = s.objects.back();
    EXPECT_EQ(teapot.name, "teapot");
    EXPECT_FALSE(teapot.castShadows);
    EXPECT_EQ(s.materials[teapot.material].name, "default");
    EXPECT_EQ(s.meshes[teapot.mesh].triangleCount(), 4032u);
}

TEST(SceneTest, VolumesAreResolvedAndValidated) {
    json doc = minimal();
    doc["volumes"] = json::parse(R"([{"name": "smoke", "path": "vdb-smoke/smoke.vdb",
                                       "density_scale": 2, "anisotropy": 0.3}])");
    Scene s = parseScene(doc, kThirdParty);
    ASSERT_EQ(s.volumes.size(), 1u);
    EXPECT_TRUE(s.volumes[0].path.is_absolute());
    EXPECT_TRUE(fs::exists(s.volumes[0].path));
    EXPECT_EQ(s.volumes[0].grid, "density");
    EXPECT_FLOAT_EQ(s.volumes[0].densityScale, 2.0f);

    doc["volumes"][0]["anisotropy"] = 1.0;
    expectContains(parseError(doc), {"/volumes/0/anisotropy", "(-1, 1)"});
    doc["volumes"][0]["anisotropy"] = 0.0;
    doc["volumes"][0]["path"] = "missing.vdb";
    expectContains(parseError(doc), {"/volumes/0/path", "missing.vdb", "does not exist"});
}
