// The `volume` technique's GPU volume construction (silhouette.comp, compact.comp) against a CPU
// double-precision count written from the edge adjacency (shadows::buildAdjacency) and the
// scene: the silhouette edges of the closed casters, the volume triangles that the depth-fail
// and the depth-pass (`zpass`) rules emit, and the caster triangles launched (a culled
// caster's must not be). The counts are integers and must agree exactly; a facing value within
// 1e-5 of the triangle's |cross| |toLight| (float world positions against double) is
// ambiguous, and the scenes are checked to have none (so the expectation stays exact).
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "shadows/volume/adjacency.h"
#include "support/test_support.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <set>

namespace veil::test {

namespace {

nlohmann::json silhouetteScene(const nlohmann::json& light, bool zpass, bool culling) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 64, "height": 48, "ambient": 0.1, "tonemap": "clamp"},
      "cameras": [{"name": "cam", "type": "perspective", "position": [5, 4.5, 6],
                   "target": [0, 0.3, 0], "fov_y": 50, "near": 0.1, "far": 40}],
      "materials": {"grey": {"base_color": 0.5, "roughness": 0.7, "metalness": 0}},
      "objects": [
        {"name": "floor", "shape": {"type": "plane", "size": [10, 10]}, "material": "grey"},
        {"name": "box", "shape": {"type": "box", "size": [1, 1.5, 1]}, "material": "grey",
         "transform": {"translate": [-1, 0.75, 0], "rotate": [0, 30, 0]}},
        {"name": "ball", "shape": {"type": "sphere", "radius": 0.6, "segments": 24, "rings": 12},
         "material": "grey", "transform": {"translate": [1.2, 1.4, 0.5]}},
        {"name": "ring", "shape": {"type": "torus", "major_radius": 0.7, "minor_radius": 0.2,
                                   "major_segments": 24, "minor_segments": 12},
         "material": "grey", "transform": {"translate": [0.3, 2.2, -1.2], "rotate": [60, 0, 20]}},
        {"name": "slab", "shape": {"type": "box", "size": [2.5, 0.2, 2.5]}, "material": "grey",
         "transform": {"translate": [-1.3, 3.5, 0.2]}},
        {"name": "hidden", "shape": {"type": "box", "size": [0.3, 0.3, 0.3]}, "material": "grey",
         "transform": {"translate": [-1.1, 2.6, 0.2]}}
      ]})");
    doc["lights"] = nlohmann::json::array({light});
    doc["render"]["shadows"] = {{"type", "volume"},
                                {"size", 256},
                                {"caster_culling", culling},
                                {"receiver_culling", culling},
                                {"clamping", false},
                                {"zpass", zpass},
                                {"grid", 64},
                                {"slices", 64}};
    return doc;
}

struct CpuCounts {
    std::uint64_t silhouetteEdges = 0, failTriangles = 0, passTriangles = 0, triangles = 0;
    int ambiguous = 0;
};

// Written from silhouette.comp's rules (its header), in double from the scene: per caster, the
// depth-pass choice (the eye-to-light segment against the caster's bounds), then per triangle
// its facing and each edge's neighbour facing from the adjacency.
CpuCounts cpuCounts(const scene::Scene& sc, bool zpass, const std::set<std::string>& culled) {
    const scene::Light& light = sc.lights.at(0);
    const bool directional = light.type == scene::LightType::Directional;
    const glm::dvec3 L =
        directional ? glm::normalize(glm::dvec3(light.direction)) : glm::dvec3(light.position);
    const glm::dvec3 eye(sc.cameras.at(0).position);
    glm::vec3 slo, shi;
    sc.bounds(slo, shi);
    const double margin = 1e-3 * std::max(double(glm::length(shi - slo)), 1e-3);
    CpuCounts n;
    for (const scene::Object& o : sc.objects) {
        if (!o.castShadows || culled.count(o.name)) continue;
        const scene::MeshData& mesh = sc.meshes[o.mesh];
        const shadows::Adjacency adj = shadows::buildAdjacency(mesh.positions, mesh.indices);
        const glm::dmat4 M(o.transform);
        std::vector<glm::dvec3> W;
        glm::dvec3 lo(1e300), hi(-1e300);
        for (const glm::vec3& p : mesh.positions) {
            W.push_back(glm::dvec3(M * glm::dvec4(glm::dvec3(p), 1.0)));
            lo = glm::min(lo, W.back());
            hi = glm::max(hi, W.back());
        }
        // Depth-pass when the segment eye -> light (a ray for a directional light) misses the
        // bounds widened by the margin (slab test).
        const glm::dvec3 d = directional ? -L : L - eye;
        double t0 = 0.0, t1 = directional ? 1e300 : 1.0;
        for (int k = 0; k < 3; ++k) {
            const double a = (lo[k] - margin - eye[k]) / d[k], b = (hi[k] + margin - eye[k]) / d[k];
            t0 = std::max(t0, std::min(a, b));
            t1 = std::min(t1, std::max(a, b));
        }
        const bool pass = zpass && t0 > t1;
        auto facing = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
            // Rotated so that the smallest index comes first (silhouette.comp's facing()).
            if (j < i && j < k)
                std::tie(i, j, k) = std::make_tuple(j, k, i);
            else if (k < i && k < j)
                std::tie(i, j, k) = std::make_tuple(k, i, j);
            const glm::dvec3 c = glm::cross(W[j] - W[i], W[k] - W[i]);
            const glm::dvec3 toLight = directional ? -L : L - W[i];
            const double f = glm::dot(c, toLight);
            if (std::abs(f) < 1e-5 * glm::length(c) * glm::length(toLight)) ++n.ambiguous;
            return f;
        };
        const std::size_t tris = adj.indices.size() / 6;
        n.triangles += tris;
        for (std::size_t t = 0; t < tris; ++t) {
            const std::uint32_t* v = &adj.indices[6 * t];
            const double f = facing(v[0], v[2], v[4]);
            const double e[3] = {facing(v[0], v[1], v[2]), facing(v[2], v[3], v[4]),
                                 facing(v[4], v[5], v[0])};
            int sides = 0;
            if (adj.closed) {
                if (f <= 0.0) continue;
                for (double x : e)
                    sides += x <= 0.0;
                n.silhouetteEdges += sides;
            } else if (f > 0.0) {
                for (double x : e)
                    sides += x <= 0.0;
            } else if (f < 0.0) {
                for (double x : e)
                    sides += x >= 0.0;
            } else {
                continue;
            }
            // Infinite extrusion: a directional light's sides are one triangle (every extruded
            // point is the same), its back cap empty; a point light's back cap at infinity is
            // dropped by depth-pass, the front cap always by depth-pass.
            const int perSide = directional ? 1 : 2;
            const int caps = pass ? 0 : (directional ? 1 : 2);
            (pass ? n.passTriangles : n.failTriangles) += caps + sides * perSide;
        }
    }
    return n;
}

nlohmann::json renderStats(const scene::Scene& sc, const gpu::ContextInfo& info) {
    frame::Renderer renderer(sc, info);
    renderer.render();
    return renderer.shadowTechnique().stats();
}

} // namespace

using ShadowVolumeSilhouetteTest = GlTest;

TEST_F(ShadowVolumeSilhouetteTest, CountsMatchCpuAdjacency) {
    const nlohmann::json directional = {{"type", "directional"},
                                        {"direction", {0.3, -1, -0.25}},
                                        {"intensity", 2.0},
                                        {"shadows", true}};
    const nlohmann::json point = {
        {"type", "point"}, {"position", {0.5, 4.5, 1.0}}, {"intensity", 30.0}, {"shadows", true}};
    // The eye inside the ring's volume from this point light: one caster stays depth-fail.
    nlohmann::json inside = point;
    inside["position"] = {0.3, 2.2, -1.2};
    for (const auto& [light, what] : {std::pair{directional, "directional"},
                                      std::pair{point, "point"}, std::pair{inside, "point, near"}})
        for (bool zpass : {false, true}) {
            const scene::Scene sc =
                scene::parseScene(silhouetteScene(light, zpass, false), sourceDir());
            const nlohmann::json s = renderStats(sc, info());
            const CpuCounts cpu = cpuCounts(sc, zpass, {});
            const std::string label = fmt::format("{}, zpass {} (stats {})", what, zpass, s.dump());
            ASSERT_EQ(cpu.ambiguous, 0) << label;
            EXPECT_GT(cpu.silhouetteEdges, 50u) << label;
            EXPECT_EQ(s.at("silhouette_edges").get<std::uint64_t>(), cpu.silhouetteEdges) << label;
            EXPECT_EQ(s.at("volume_triangles").get<std::uint64_t>(),
                      cpu.failTriangles + cpu.passTriangles)
                << label;
            EXPECT_EQ(s.at("depth_pass_triangles").get<std::uint64_t>(), cpu.passTriangles)
                << label;
            EXPECT_EQ(s.at("submitted_triangles").get<std::uint64_t>(), cpu.triangles) << label;
            if (zpass) {
                EXPECT_GT(cpu.passTriangles, 0u) << label;
                if (light == inside) {
                    EXPECT_GT(cpu.failTriangles, 0u) << label;
                }
            } else {
                EXPECT_EQ(cpu.passTriangles, 0u) << label;
            }
        }
}

// [Eisemann06 sec. 3.2] culling, not just emitting nothing: the triangles that silhouette.comp
// launches are exactly those of the casters that classify.comp did not cull (the CPU sums them from
// the scene's meshes), and where GL_ARB_pipeline_statistics_query exists the compute invocations
// are those launches rounded up to 64-wide workgroups plus compact.comp's two 256-wide ones.
TEST_F(ShadowVolumeSilhouetteTest, CulledCastersAreNotLaunched) {
    nlohmann::json light = {{"type", "directional"},
                            {"direction", {0.15, -1, 0.1}},
                            {"intensity", 2.0},
                            {"shadows", true}};
    const scene::Scene sc = scene::parseScene(silhouetteScene(light, true, true), sourceDir());
    const nlohmann::json s = renderStats(sc, info());
    std::set<std::string> culled;
    for (const auto& entry : s.at("culled_objects"))
        culled.insert(entry.at(1).get<std::string>());
    ASSERT_EQ(culled.count("hidden"), 1u) << s.dump(); // behind the slab (caster culling)
    const CpuCounts all = cpuCounts(sc, true, {}), kept = cpuCounts(sc, true, culled);
    ASSERT_LT(kept.triangles, all.triangles);
    const auto submitted = s.at("submitted_triangles").get<std::uint64_t>();
    EXPECT_EQ(submitted, kept.triangles) << s.dump();
    EXPECT_EQ(s.at("caster_triangles").get<std::uint64_t>(), all.triangles);
    EXPECT_EQ(s.at("volume_triangles").get<std::uint64_t>(),
              kept.failTriangles + kept.passTriangles)
        << s.dump();
    if (s.at("pipeline").is_object()) {
        const std::uint64_t expected = 2 * 256 + (submitted + 63) / 64 * 64;
        EXPECT_EQ(s.at("pipeline")
                      .at("silhouettes")
                      .at("compute_shader_invocations")
                      .get<std::uint64_t>(),
                  expected);
        EXPECT_EQ(
            s.at("pipeline").at("volumes").at("clipping_input_primitives").get<std::uint64_t>(),
            s.at("volume_triangles").get<std::uint64_t>());
    } else {
        GTEST_LOG_(INFO) << "no pipeline statistics: " << s.at("pipeline").dump();
    }
}

} // namespace veil::test
