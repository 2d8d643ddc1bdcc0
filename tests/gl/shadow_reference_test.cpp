// The `reference` shadow technique against a CPU double-precision ray caster written for this
// test: from a floor point toward the light, every shadow-casting triangle of the scene
// (Moller-Trumbore in double) multiplies 1 - alpha + alpha T [McGuire16 Eq. 2] for a transparent
// material and 0 for an opaque one, and the density volumes' transmittance comes from the fog's
// CPU reference (src/integrators/cpu_reference.h: OpenVDB trilinear sampling, in double). The GPU's
// visibility is read as the ratio of the floor's radiance with and without shadows (the same
// BRDF and light on both sides, so only the visibility and RGBA16F rounding remain).
// Compared at every 4th floor pixel whose neighbourhood (+-0.75 pixel) has one CPU visibility
// (the map's texel resolution smears edges: those pixels are skipped), under a spot light
// (perspective view) and a directional one.
#include "gl_fixture.h"
#include "ray_cast_shadows.h"

#include "frame/renderer.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "support/test_support.h"
#include "integrators/cpu_reference.h"
#include "grid/density_grid.h"

#include <glm/glm.hpp>

#include <array>
#include <cmath>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

using Rgb = std::array<double, 3>;

using ray_cast::trianglesTransmittance;

struct CpuShadows {
    const scene::Scene& sc;
    volume::CpuFogReference fog;
    Rgb at(const glm::dvec3& P) const {
        const scene::Light& l = sc.lights[0];
        glm::dvec3 d;
        double tMax;
        ray_cast::towardLight(l, P, d, tMax);
        Rgb T = trianglesTransmittance(sc, P, d, tMax);
        const double media = fog.transmittanceToLight(P, 0, 4096);
        for (double& c : T)
            c *= media;
        return T;
    }
};

std::vector<openvdb::FloatGrid::ConstPtr> gridsOf(const scene::Scene& sc) {
    std::vector<openvdb::FloatGrid::ConstPtr> grids;
    for (const auto& v : sc.volumes)
        if (v.procedural != "homogeneous") grids.push_back(volume::loadVolume(v));
    return grids;
}

ImageF render(const scene::Scene& sc, const gpu::ContextInfo& info) {
    frame::Renderer renderer(sc, info);
    renderer.render();
    return renderer.readHdr();
}

void compare(nlohmann::json doc, const gpu::ContextInfo& info, const char* what) {
    doc["render"]["shadows"] = {{"type", "reference"}, {"size", 1024}, {"media_steps", 512}};
    doc["render"]["fog_steps"] = 8; // the camera rays' fog is not what is compared
    const scene::Scene sc = scene::parseScene(doc, sourceDir());
    nlohmann::json unshadowed = doc;
    unshadowed["lights"][0]["shadows"] = false;
    const scene::Scene sc0 = scene::parseScene(unshadowed, sourceDir());
    unshadowed["volumes"] = nlohmann::json::array();
    const scene::Scene sc1 = scene::parseScene(unshadowed, sourceDir());
    const ImageF lit = render(sc, info), free = render(sc1, info);
    // Pixels whose camera ray crosses the fog (the unshadowed frame with and without the
    // volumes differs) are skipped: the fog in front of the floor is not the light's visibility.
    const ImageF freeWithFog = render(sc0, info);
    const CpuShadows cpu{sc, volume::CpuFogReference(sc, gridsOf(sc))};
    int compared = 0, shadowed = 0;
    for (int y = 2; y < 126; y += 4)
        for (int x = 2; x < 126; x += 4) {
            const glm::dvec3 P(ss::centre(x), 0.0, ss::centre(y));
            // Only floor the camera (straight above) sees directly: nothing over the point.
            const Rgb above = trianglesTransmittance(sc, P, {0.0, 1.0, 0.0}, 1e30);
            if (above[0] < 1.0 || above[1] < 1.0 || above[2] < 1.0) continue;
            const Rgb want = cpu.at(P);
            bool edge = false;
            for (const auto& o : {glm::dvec2(-0.75, 0), glm::dvec2(0.75, 0), glm::dvec2(0, -0.75),
                                  glm::dvec2(0, 0.75)}) {
                const Rgb n = cpu.at(P + glm::dvec3(o.x, 0.0, o.y) * (8.0 / 128.0));
                for (int c = 0; c < 3; ++c)
                    edge = edge || std::abs(n[c] - want[c]) > 1e-3;
            }
            if (edge) continue;
            const double a = ss::ambient();
            for (int c = 0; c < 3; ++c)
                if (std::abs(freeWithFog.at(x, y, c) - free.at(x, y, c)) > 1e-4) goto next;
            for (int c = 0; c < 3; ++c) {
                const double denom = free.at(x, y, c) - a;
                if (denom < 0.02) goto next; // outside the light (spot cone)
            }
            for (int c = 0; c < 3; ++c) {
                const double got = (lit.at(x, y, c) - a) / (free.at(x, y, c) - a);
                // float32 products, 512-step optical depth (half-float densities) and RGBA16F
                // rounding of both renders: 1% of T plus 2e-3.
                EXPECT_NEAR(got, want[c], 1e-2 * want[c] + 2e-3)
                    << what << " pixel (" << x << ", " << y << ") channel " << c;
            }
            ++compared;
            if (want[0] < 0.9) ++shadowed;
        next:;
        }
    EXPECT_GT(compared, 200) << what;
    EXPECT_GT(shadowed, 20) << what << ": the scene must put shadows where they are compared";
}

nlohmann::json mixedScene() {
    // Stained glass, a coverage card, an opaque box and a fog slab over the floor.
    nlohmann::json doc = ss::base({{"type", "reference"}});
    ss::addPane(doc, "stained", 1.2, 1.0, {0.8, 0.5, 0.2});
    doc["materials"]["card"] = {{"base_color", 0.2}, {"alpha", 0.6}};
    doc["objects"].push_back({{"shape", {{"type", "plane"}, {"size", {1.0, 1.0}}}},
                              {"material", "card"},
                              {"transform", {{"translate", {-2.0, 0.8, 1.5}}}}});
    doc["objects"].push_back({{"shape", {{"type", "box"}, {"size", {0.6, 0.6, 0.6}}}},
                              {"material", "grey"},
                              {"transform", {{"translate", {-1.5, 0.3, -2.0}}}}});
    ss::addFogSlab(doc, 0.6, 0.8, 1.0, 0.05);
    doc["volumes"][0]["transform"]["translate"] = {1.5, 1.6, -1.5};
    return doc;
}

} // namespace

class ShadowReferenceTest : public GlTest {};

TEST_F(ShadowReferenceTest, DirectionalLightMatchesTheCpuRayCaster) {
    compare(mixedScene(), info(), "directional");
}

TEST_F(ShadowReferenceTest, SpotLightMatchesTheCpuRayCaster) {
    nlohmann::json doc = mixedScene();
    doc["lights"][0] = {{"type", "spot"},
                        {"position", {-1.0, 6.0, 0.5}},
                        {"target", {0.5, 0.0, -0.5}},
                        {"outer_cone", 40},
                        {"inner_cone", 35},
                        {"intensity", 60.0},
                        {"shadows", true}};
    compare(doc, info(), "spot");
}

} // namespace veil::test
