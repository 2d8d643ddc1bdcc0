// Analytic shadow scenes shared by the shadow techniques' tests (issue: shadows from
// everything that is not opaque). All are an 8x8 grey floor (albedo 0.5, roughness 0.7) seen
// from straight above by a 128x128 orthographic camera (16 px per unit), lit by one
// directional light travelling along (s, -s, 0), s = 1/sqrt(2): a caster at height h over the
// origin throws its shadow h to the +x side, so the floor around (1.5, 0, 0) is in the shadow
// of a caster over x in [-1, 1] at height 1 but not under it (the camera sees that floor
// directly, not through the caster). Expected radiance: ambient + T x E x brdfCos (per channel)
// with tests/support/analytic_shading.h; a technique's test states its own tolerance.
#pragma once

#include "support/analytic_shading.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace veil::test::shadow_scenes {

inline constexpr double kAmbientFactor = 0.1;
inline constexpr double kAlbedo = 0.5;
inline constexpr double kIntensity = 2.0;

// The floor, camera and light; `shadows` is the render.shadows value (a technique object).
inline nlohmann::json base(const nlohmann::json& shadows) {
    const double s = 1.0 / std::sqrt(2.0);
    nlohmann::json doc = nlohmann::json::parse(R"({
      "render": {"width": 128, "height": 128, "ambient": 0.1, "tonemap": "clamp"},
      "cameras": [{"name": "top", "type": "orthographic", "position": [0, 10, 0],
                   "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 8, "near": 1, "far": 20}],
      "materials": {"grey": {"base_color": 0.5, "roughness": 0.7, "metalness": 0}},
      "objects": [{"name": "floor", "shape": {"type": "plane", "size": [8, 8]},
                   "material": "grey"}]})");
    doc["render"]["shadows"] = shadows;
    doc["lights"] = nlohmann::json::array({{{"type", "directional"},
                                            {"direction", {s, -s, 0}},
                                            {"intensity", kIntensity},
                                            {"shadows", true}}});
    return doc;
}

// A horizontal 2x2 pane at height y over the origin with coverage `alpha` and transmission
// `t` ([McGuire16 Eq. 2]: it lets 1 - alpha + alpha t through). Adds its material under `name`.
inline void addPane(nlohmann::json& doc, const std::string& name, double y, double alpha,
                    const nlohmann::json& t) {
    doc["materials"][name] = {
        {"base_color", 0.0}, {"roughness", 0.5}, {"alpha", alpha}, {"transmission", t}};
    doc["objects"].push_back({{"name", name},
                              {"shape", {{"type", "plane"}, {"size", {2, 2}}}},
                              {"material", name},
                              {"transform", {{"translate", {0, y, 0}}}}});
}

// A homogeneous box of fog (procedural "box", density 1 x density_scale `sigma`) 2 wide in x
// and z and `thickness` high, its bottom at height `bottom`, over the origin. The light
// crosses it along a path sqrt(2) x thickness long: optical depth tau = sigma sqrt(2) thickness.
inline void addFogSlab(nlohmann::json& doc, double sigma, double thickness, double bottom = 1.0,
                       double voxelSize = 0.05, double albedo = 0.0) {
    doc["volumes"].push_back({{"name", "slab"},
                              {"procedural", "box"},
                              {"size", {2.0, thickness, 2.0}},
                              {"voxel_size", voxelSize},
                              {"density_scale", sigma},
                              {"albedo", albedo},
                              {"transform", {{"translate", {0, bottom + 0.5 * thickness, 0}}}}});
}

// Stained glass over fog, seen from the side: a large red-tinted pane (6x6 at height 2.6)
// covers everything the light reaches below it, and a scattering slab (albedo 0.8, 2 wide, from
// height 1 to 2) under it is seen by an orthographic camera looking along -z at height 1.5, so
// the pixel at the image centre sees only in-scattered light that came through the pane (plus
// the slab's own grey self-shadowing): its colour ratios must be the pane's, T_r / T_g.
inline nlohmann::json stainedGlassOverFog(const nlohmann::json& shadows) {
    nlohmann::json doc = base(shadows);
    doc["cameras"] = nlohmann::json::parse(
        R"([{"name": "side", "type": "orthographic", "position": [0, 1.5, 10],
             "target": [0, 1.5, 0], "ortho_height": 4, "near": 1, "far": 30}])");
    doc["render"]["background"] = 0.0;
    doc["render"]["ambient"] = 0.0;
    doc["render"]["fog_jitter"] = false;
    doc["objects"] = nlohmann::json::array();
    doc["materials"]["red glass"] = {{"base_color", 0.0},
                                     {"roughness", 0.5},
                                     {"alpha", 1.0},
                                     {"transmission", {0.9, 0.3, 0.15}}};
    doc["objects"].push_back({{"name", "pane"},
                              {"shape", {{"type", "plane"}, {"size", {6, 6}}}},
                              {"material", "red glass"},
                              {"transform", {{"translate", {0, 2.6, 0}}}}});
    addFogSlab(doc, 0.5, 1.0, 1.0, 0.05, 0.8);
    return doc;
}
inline constexpr double kShaftT[3] = {0.9, 0.3, 0.15};

// Pixel of world x (or z) on the 128 px floor image, and the world coordinate of its centre.
inline int px(double x) { return static_cast<int>(std::floor((x + 4.0) / 8.0 * 128.0)); }
inline double centre(int p) { return -4.0 + (p + 0.5) * 8.0 / 128.0; }

// Unshadowed floor radiance from the light (without the ambient term).
inline double litFloor() {
    using namespace analytic;
    const double s = 1.0 / std::sqrt(2.0);
    return kIntensity * brdfCos(kAlbedo, 0.7, {0, 1, 0}, {0, 1, 0}, {-s, s, 0});
}
inline double ambient() { return kAmbientFactor * kAlbedo; }

// Where to read: in the shadow of the casters over the origin at height 1 (x = 1.5, z = 0)
// and fully lit (x = -3, z = 3).
inline constexpr double kShadowX = 1.5, kShadowZ = 0.0;
inline constexpr double kLitX = -3.0, kLitZ = 3.0;

} // namespace veil::test::shadow_scenes
