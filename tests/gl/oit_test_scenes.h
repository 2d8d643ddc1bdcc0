// Scenes for the OIT GL tests, built in code: an orthographic camera looking down -z at
// camera-facing emission-only planes, no lights and ambient 0, so each plane contributes
// exactly alpha * emission and modulates what is behind it by 1 - alpha + alpha * T.
#pragma once

#include "oit/cpu/composite.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace veil::test {

struct TestPlane {
    glm::dvec3 emission{0.0};
    double alpha = 1.0;
    glm::dvec3 transmission{0.0};
    double z = 0.0;              // world z; view depth = 10 - z
    glm::dvec2 center{0.0, 0.0}; // world x, y
    double size = 4.0;           // side length (the view is 2 x 2 world units at aspect 1)
};

inline double planeDepth(const TestPlane& p) { return 10.0 - p.z; }

inline oit::cpu::Fragment planeFragment(const TestPlane& p) {
    return oit::cpu::makeFragment(planeDepth(p), p.emission, p.alpha, p.transmission);
}

// Planes are submitted in the given order. Image `width` x `height` at aspect width/height,
// view height 2 world units centred on the origin.
inline nlohmann::json planeScene(const std::vector<TestPlane>& planes, glm::dvec3 background,
                                 int width, int height) {
    nlohmann::json doc;
    doc["render"] = {{"width", width},
                     {"height", height},
                     {"ambient", 0.0},
                     {"tonemap", "clamp"},
                     {"background", {background.r, background.g, background.b}}};
    doc["cameras"] = nlohmann::json::array({{{"name", "front"},
                                             {"type", "orthographic"},
                                             {"position", {0, 0, 10}},
                                             {"target", {0, 0, 0}},
                                             {"ortho_height", 2.0},
                                             {"near", 1.0},
                                             {"far", 20.0}}});
    doc["materials"] = nlohmann::json::object();
    doc["objects"] = nlohmann::json::array();
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const TestPlane& p = planes[i];
        const std::string name = fmt::format("m{}", i);
        doc["materials"][name] = {
            {"base_color", 0.0},
            {"emission", {p.emission.r, p.emission.g, p.emission.b}},
            {"alpha", p.alpha},
            {"transmission", {p.transmission.r, p.transmission.g, p.transmission.b}}};
        doc["objects"].push_back(
            {{"shape", {{"type", "plane"}, {"size", {p.size, p.size}}}},
             {"material", name},
             {"transform",
              {{"translate", {p.center.x, p.center.y, p.z}}, {"rotate", {90, 0, 0}}}}});
    }
    return doc;
}

} // namespace veil::test
