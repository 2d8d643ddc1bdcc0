// The `volume` shadow technique (src/shadows/volume): stencil shadow volumes against a CPU
// double-precision ray cast (tests/gl/ray_cast_shadows.h) from each pixel's world position
// (the frame's depth buffer, unprojected in double) to the light. Shadow volumes are exact per
// pixel, so the tolerance is zero differing pixels; only pixels whose 3x3 neighbourhood holds
// both CPU answers (the one-pixel band where the shadow edge crosses the pixel, where the
// float depth's unprojection may land on either side) are skipped. Then the culling and
// clamping of [Eisemann06 sec. 3.2] must leave the stencil's answer bit-exact while the stencil
// fill drops, and meshes that are not closed must be handled (per-triangle volumes) or refused.
#include "gl_fixture.h"
#include "ray_cast_shadows.h"

#include "frame/renderer.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "shadows/volume/adjacency.h"
#include "support/test_support.h"

#include <glm/glm.hpp>

#include <cctype>
#include <cstdlib>
#include <filesystem>

namespace veil::test {

namespace {

// Ray-cast hits nearer than this to the unprojected pixel are its own surface (the float depth
// puts P up to ~1e-4 off it at these distances); a real occluder that close is only at a
// contact line, inside the edge band.
constexpr double kSelfHit = 2e-3;

// Floor, boxes, a sphere and a torus (closed meshes), under `light`, seen by a perspective
// camera from `eye`.
nlohmann::json scene(const nlohmann::json& light, const nlohmann::json& shadows,
                     const nlohmann::json& eye = {5.0, 4.5, 6.0},
                     const nlohmann::json& target = {0.0, 0.3, 0.0}) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 96, "height": 72, "ambient": 0.1, "tonemap": "clamp"},
      "materials": {"grey": {"base_color": 0.5, "roughness": 0.7, "metalness": 0}},
      "objects": [
        {"name": "floor", "shape": {"type": "plane", "size": [10, 10]}, "material": "grey"},
        {"name": "box", "shape": {"type": "box", "size": [1, 1.5, 1]}, "material": "grey",
         "transform": {"translate": [-1, 0.75, 0], "rotate": [0, 30, 0]}},
        {"name": "ball", "shape": {"type": "sphere", "radius": 0.6, "segments": 24, "rings": 12},
         "material": "grey", "transform": {"translate": [1.2, 1.4, 0.5]}},
        {"name": "ring", "shape": {"type": "torus", "major_radius": 0.7, "minor_radius": 0.2,
                                   "major_segments": 24, "minor_segments": 12},
         "material": "grey", "transform": {"translate": [0.3, 2.2, -1.2], "rotate": [60, 0, 20]}}
      ]})");
    doc["cameras"] = {{{"name", "cam"},
                       {"type", "perspective"},
                       {"position", eye},
                       {"target", target},
                       {"fov_y", 50},
                       {"near", 0.1},
                       {"far", 40}}};
    doc["lights"] = nlohmann::json::array({light});
    doc["render"]["shadows"] = shadows;
    return doc;
}

nlohmann::json spot() {
    return {{"type", "spot"},    {"position", {-2.5, 6, 2}}, {"direction", {0.35, -1, -0.3}},
            {"intensity", 40.0}, {"inner_cone", 35},         {"outer_cone", 45},
            {"shadows", true}};
}
nlohmann::json directional() {
    return {{"type", "directional"},
            {"direction", {0.3, -1, -0.25}},
            {"intensity", 2.0},
            {"shadows", true}};
}
nlohmann::json point() {
    return {
        {"type", "point"}, {"position", {0.5, 4.5, 1.0}}, {"intensity", 30.0}, {"shadows", true}};
}

nlohmann::json volumeShadows(bool culling) {
    return {{"type", "volume"},
            {"size", 512},
            {"caster_culling", culling},
            {"receiver_culling", culling},
            {"clamping", culling},
            {"grid", 64},
            {"slices", 64}};
}

struct Frame {
    int w = 0, h = 0;
    std::vector<float> depth;       // the frame's depth buffer, row 0 at the bottom
    std::vector<unsigned char> vis; // layer 0 of shadow.volume
    glm::dmat4 invViewProjection{1.0};
    nlohmann::json stats;
};

Frame renderFrame(const scene::Scene& sc, const gpu::ContextInfo& info) {
    frame::Renderer renderer(sc, info);
    renderer.render();
    Frame f;
    const int kW = renderer.width(), kH = renderer.height();
    f.w = kW;
    f.h = kH;
    f.depth.resize(kW * kH);
    f.vis.resize(kW * kH);
    const gpu::Texture* depth = renderer.resourceTexture("depth");
    const gpu::Texture* vis = renderer.resourceTexture("shadow.volume");
    EXPECT_TRUE(depth && vis);
    if (!depth || !vis) return f;
    glGetTextureImage(depth->id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, int(f.depth.size() * 4),
                      f.depth.data());
    glGetTextureSubImage(vis->id(), 0, 0, 0, 0, kW, kH, 1, GL_RED, GL_UNSIGNED_BYTE,
                         int(f.vis.size()), f.vis.data());
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    const double aspect = double(kW) / kH;
    const scene::Camera& cam = renderer.camera();
    f.invViewProjection =
        glm::inverse(glm::dmat4(cam.projection(float(aspect))) * glm::dmat4(cam.view()));
    f.stats = renderer.shadowTechnique().stats();
    return f;
}

// Compares the volume's visibility with the ray cast at every covered pixel; returns the
// number of compared pixels. `differing` gets the pixels that differ away from the band.
int compareWithRayCast(const scene::Scene& sc, const Frame& f, int& differing, int& inShadow,
                       const char* what) {
    const int kW = f.w, kH = f.h;
    std::vector<int> cpu(kW * kH, -1);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float z = f.depth[y * kW + x];
            if (z >= 1.0f) continue;
            const glm::dvec4 ndc((x + 0.5) / kW * 2.0 - 1.0, (y + 0.5) / kH * 2.0 - 1.0,
                                 double(z) * 2.0 - 1.0, 1.0);
            const glm::dvec4 w = f.invViewProjection * ndc;
            cpu[y * kW + x] = int(ray_cast::opaqueVisibility(sc, 0, glm::dvec3(w) / w.w, kSelfHit));
        }
    // VEIL_TEST_IMAGES=<dir>: <what>.png, red = the volume's visibility, green = the ray cast's,
    // blue = the skipped band (for looking at the comparison).
    if (const char* dir = std::getenv("VEIL_TEST_IMAGES")) {
        ImageF img(kW, kH, 3);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const int r = kH - 1 - y, c = cpu[y * kW + x];
                img.at(x, r, 0) = f.vis[y * kW + x] / 255.0f;
                img.at(x, r, 1) = c < 0 ? 0.0f : float(c);
                img.at(x, r, 2) = c < 0 ? 0.3f : 0.0f;
            }
        std::string name = what;
        for (char& ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
        io::writeImage(std::filesystem::path(dir) / (name + ".png"), img);
    }
    int compared = 0;
    differing = inShadow = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const int want = cpu[y * kW + x];
            if (want < 0) continue;
            bool band = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= kW || ny >= kH) continue;
                    const int n = cpu[ny * kW + nx];
                    band |= n >= 0 && n != want;
                }
            if (band) continue;
            ++compared;
            inShadow += want == 0;
            const int got = f.vis[y * kW + x] > 127 ? 1 : 0;
            if (got != want) {
                if (differing < 8)
                    ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") volume " << got
                                  << ", ray cast " << want;
                ++differing;
            }
        }
    return compared;
}

void expectMatchesRayCast(const nlohmann::json& doc, const gpu::ContextInfo& info,
                          const char* what) {
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    const Frame f = renderFrame(sc, info);
    int differing = 0, inShadow = 0;
    const int compared = compareWithRayCast(sc, f, differing, inShadow, what);
    EXPECT_EQ(differing, 0) << what;
    // Not a vacuous pass: most of the image is compared and both answers occur.
    EXPECT_GT(compared, f.w * f.h / 3) << what;
    EXPECT_GT(inShadow, 50) << what;
    EXPECT_GT(compared - inShadow, 50) << what;
}

} // namespace

TEST(ShadowVolumeAdjacency, ClosedOpenAndNonManifold) {
    const scene::MeshData box = scene::makeBox({1, 2, 3});
    const shadows::Adjacency a = shadows::buildAdjacency(box.positions, box.indices);
    EXPECT_TRUE(a.closed) << a.reason; // 24 split-normal vertices weld to 8 corners
    EXPECT_EQ(a.indices.size(), box.indices.size() * 2);
    const scene::MeshData plane = scene::makePlane({1, 1});
    const shadows::Adjacency p = shadows::buildAdjacency(plane.positions, plane.indices);
    EXPECT_FALSE(p.closed);
    EXPECT_EQ(p.boundaryEdges, 4);
    EXPECT_NE(p.reason.find("open"), std::string::npos) << p.reason;
    // Three triangles on one edge.
    const std::vector<glm::vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    const shadows::Adjacency n = shadows::buildAdjacency(v, {0, 1, 2, 1, 0, 3, 0, 1, 4});
    EXPECT_FALSE(n.closed);
    EXPECT_GT(n.nonManifoldEdges, 0);
    const scene::MeshData torus = scene::makeTorus(1.0f, 0.3f, 12, 8);
    EXPECT_TRUE(shadows::buildAdjacency(torus.positions, torus.indices).closed);
    const scene::MeshData sphere = scene::makeSphere(1.0f, 12, 6);
    EXPECT_TRUE(shadows::buildAdjacency(sphere.positions, sphere.indices).closed);
}

using ShadowVolumeTest = GlTest;

// The foundation's shadow test (tests/gl/lighting_test.cpp) with volumes and no bias: the
// floor in the unit box's shadow gets only the ambient term, the lit floor the analytic BRDF
// (orthographic camera: finite extrusion), and every pixel matches the ray cast.
TEST_F(ShadowVolumeTest, BoxShadowWithoutBiasIsAmbientOnly) {
    const double s = 1.0 / std::sqrt(2.0);
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 128, "height": 128, "ambient": 0.1, "tonemap": "clamp"},
      "cameras": [{"name": "top", "type": "orthographic", "position": [0, 10, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 8, "near": 1, "far": 20}],
      "materials": {"grey": {"base_color": 0.5, "roughness": 0.7, "metalness": 0}},
      "objects": [
        {"shape": {"type": "plane", "size": [8, 8]}, "material": "grey"},
        {"shape": {"type": "box", "size": [1, 1, 1]}, "material": "grey",
         "transform": {"translate": [0, 0.5, 0]}}
      ]})");
    doc["lights"] = nlohmann::json::array({{{"type", "directional"},
                                            {"direction", {s, -s, 0}},
                                            {"intensity", 2.0},
                                            {"shadows", true}}});
    doc["render"]["shadows"] = {{"type", "volume"}, {"bias", 0.0}, {"pcf_radius", 0}};
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    frame::Renderer renderer(sc, info());
    renderer.render();
    const ImageF img = renderer.readHdr();
    const double ambient = 0.1 * 0.5;
    auto px = [](double x) { return static_cast<int>(std::floor((x + 4.0) / 8.0 * 128.0)); };
    // The whole shadow, x in (0.5, 1.5) on the floor row z = 0 (pixel centres), ambient only;
    // just outside it lit.
    for (int p = px(0.5); p <= px(1.5); ++p) {
        const double x = -4.0 + (p + 0.5) / 16.0;
        if (x <= 0.5 || x >= 1.5) continue;
        EXPECT_NEAR(img.at(p, px(0.0), 0), ambient, 2e-3) << "floor x = " << x;
    }
    const double lit = img.at(px(1.6), px(0.0), 0);
    EXPECT_GT(lit, 3.0 * ambient);
    expectMatchesRayCast(doc, info(), "box on the floor, no bias");
}

TEST_F(ShadowVolumeTest, SpotLightMatchesRayCast) {
    expectMatchesRayCast(scene(spot(), volumeShadows(false)), info(), "spot, unculled");
    expectMatchesRayCast(scene(spot(), volumeShadows(true)), info(), "spot, culled + clamped");
}

TEST_F(ShadowVolumeTest, DirectionalLightMatchesRayCast) {
    nlohmann::json low = directional(); // long shadows across the floor
    low["direction"] = {0.9, -1, -0.6};
    expectMatchesRayCast(scene(low, volumeShadows(false)), info(), "directional");
    expectMatchesRayCast(scene(low, volumeShadows(true)), info(), "directional, culled + clamped");
}

TEST_F(ShadowVolumeTest, PointLightMatchesRayCast) {
    expectMatchesRayCast(scene(point(), volumeShadows(true)), info(), "point");
}

TEST_F(ShadowVolumeTest, CameraInsideAShadowVolume) {
    // Under the box's shadow from the directional light, between the box and its shadow on the
    // floor, looking across the floor: the near plane cuts the volume (depth-fail with caps).
    nlohmann::json doc =
        scene(directional(), volumeShadows(false), {-0.35, 0.15, -0.4}, {2.0, -0.5, -1.8});
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    // The camera really is in the shadow.
    ASSERT_EQ(ray_cast::opaqueVisibility(sc, 0, {-0.35, 0.15, -0.4}), 0.0);
    expectMatchesRayCast(doc, info(), "camera in a volume");
    doc["render"]["shadows"] = volumeShadows(true);
    expectMatchesRayCast(doc, info(), "camera in a volume, culled + clamped");
}

TEST_F(ShadowVolumeTest, OpenMeshCastsItsTrianglesShadow) {
    // A floating open quad (a plane: 4 boundary edges), turned over so that it faces away from
    // the light: its volume is extruded per triangle (a warning names it), wound the other
    // way, and still matches the ray cast.
    nlohmann::json doc = scene(spot(), volumeShadows(false));
    doc["objects"].push_back(
        {{"name", "card"},
         {"shape", {{"type", "plane"}, {"size", {1.2, 0.8}}}},
         {"material", "grey"},
         {"transform", {{"translate", {1.5, 2.5, -1.5}}, {"rotate", {200, 0, 10}}}}});
    expectMatchesRayCast(doc, info(), "open quad caster");
}

TEST_F(ShadowVolumeTest, ParticleCasterIsRefusedWithOneLine) {
    nlohmann::json doc = scene(spot(), volumeShadows(false));
    doc["objects"].push_back(
        {{"name", "smoke"},
         {"shape",
          {{"type", "particles"}, {"count", 20}, {"radius", 0.5}, {"particle_size", 0.05}}},
         {"material", "grey"}});
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    try {
        frame::Renderer renderer(sc, info());
        renderer.render();
        FAIL() << "a particle caster was accepted";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("'smoke'"), std::string::npos) << m;
        EXPECT_NE(m.find("particle"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

// [Eisemann06 sec. 3.2]: a tall box hidden from the light behind a wide slab (caster culling),
// casters whose shadow falls where the camera sees no receiver (receiver culling), and a camera
// that sees only the near part of the light's depth range (clamping). Every combination must give
// the unculled visibility bit for bit, and the stencil fill must drop; so must depth-pass
// counting (`zpass`, on in all of them) against depth-fail for every caster.
TEST_F(ShadowVolumeTest, CullingAndClampingAreBitExactAndCutFill) {
    nlohmann::json light = directional();
    light["direction"] = {0.15, -1, 0.1};
    nlohmann::json doc = scene(light, volumeShadows(false), {4.0, 3.0, 4.5}, {0.0, 0.0, 0.0});
    doc["objects"].push_back({{"name", "slab"},
                              {"shape", {{"type", "box"}, {"size", {2.5, 0.2, 2.5}}}},
                              {"material", "grey"},
                              {"transform", {{"translate", {-1.3, 3.5, 0.2}}}}});
    doc["objects"].push_back({{"name", "hidden"},
                              {"shape", {{"type", "box"}, {"size", {0.3, 0.3, 0.3}}}},
                              {"material", "grey"},
                              {"transform", {{"translate", {-1.1, 2.6, 0.2}}}}});
    // Above the view, beyond the floor's far edge: its volume crosses the screen but reaches no
    // receiver (receiver culling; a caster the camera sees is its own receiver).
    doc["objects"].push_back({{"name", "beyond"},
                              {"shape", {{"type", "box"}, {"size", {0.6, 0.6, 0.6}}}},
                              {"material", "grey"},
                              {"transform", {{"translate", {-6.5, 6.0, -6.5}}}}});
    // Receivers fill only part of the depth range: a tall column far behind the camera's
    // view makes the light's range deep, the floor is at the bottom.
    doc["objects"].push_back({{"name", "tower"},
                              {"shape", {{"type", "box"}, {"size", {0.4, 8.0, 0.4}}}},
                              {"material", "grey"},
                              {"transform", {{"translate", {-4.5, 4.0, -4.5}}}}});
    auto run = [&](bool caster, bool receiver, bool clamp, bool zpass = true) {
        nlohmann::json s = volumeShadows(false);
        s["zpass"] = zpass;
        s["caster_culling"] = caster;
        s["receiver_culling"] = receiver;
        s["clamping"] = clamp;
        doc["render"]["shadows"] = s;
        const scene::Scene sc = scene::parseScene(doc, sourceDir());
        return renderFrame(sc, info());
    };
    const Frame none = run(false, false, false);
    {
        const scene::Scene sc = scene::parseScene(doc, sourceDir());
        int differing = 0, inShadow = 0;
        compareWithRayCast(sc, none, differing, inShadow, "culling scene, unculled");
        EXPECT_EQ(differing, 0);
        EXPECT_GT(inShadow, 100);
    }
    const Frame fail = run(false, false, false, false);
    {
        int diff = 0;
        for (std::size_t i = 0; i < fail.vis.size(); ++i)
            diff += fail.vis[i] != none.vis[i];
        EXPECT_EQ(diff, 0) << "depth-fail everywhere against depth-pass where possible";
        EXPECT_EQ(fail.stats.at("depth_pass_triangles").get<int>(), 0);
        EXPECT_GT(none.stats.at("depth_pass_triangles").get<int>(), 0);
        EXPECT_LT(none.stats.at("volume_triangles").get<int>(),
                  fail.stats.at("volume_triangles").get<int>());
    }
    const std::uint64_t fill0 = none.stats.at("stencil_fragments").get<std::uint64_t>();
    ASSERT_GT(fill0, 0u);
    struct Combo {
        bool caster, receiver, clamp, zpass = true;
    };
    // (Depth-fail as well with clamping: there every clamped volume's fan back cap counts.)
    for (const Combo c : {Combo{true, false, false}, Combo{false, true, false},
                          Combo{false, false, true}, Combo{true, true, true},
                          Combo{false, false, true, false}, Combo{true, true, true, false}}) {
        const Frame f = run(c.caster, c.receiver, c.clamp, c.zpass);
        int diff = 0;
        for (std::size_t i = 0; i < f.vis.size(); ++i)
            diff += f.vis[i] != none.vis[i];
        const std::string what =
            fmt::format("caster culling {}, receiver culling {}, clamping {}, zpass {}", c.caster,
                        c.receiver, c.clamp, c.zpass);
        EXPECT_EQ(diff, 0) << what;
        const std::uint64_t fill = f.stats.at("stencil_fragments").get<std::uint64_t>();
        // (against the unculled fill of the same counting)
        EXPECT_LT(fill, c.zpass ? fill0 : fail.stats.at("stencil_fragments").get<std::uint64_t>())
            << what << " (stats " << f.stats.dump() << ")";
        if (c.caster || c.receiver) {
            EXPECT_GE(f.stats.at("culled").get<int>(), 1) << what;
        }
        if (c.clamp) {
            EXPECT_GE(f.stats.at("clamped").get<int>(), 1) << what;
            // Clamped closed volumes close with a fan over their silhouette, not back caps:
            // one fan triangle per silhouette edge of the clamped casters.
            EXPECT_GT(f.stats.at("fan_triangles").get<int>(), 0) << what;
            EXPECT_LE(f.stats.at("fan_triangles").get<int>(),
                      f.stats.at("silhouette_edges").get<int>())
                << what;
        }
    }
}

} // namespace veil::test
