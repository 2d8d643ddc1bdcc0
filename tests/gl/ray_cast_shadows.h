// CPU double-precision ray caster against a scene's shadow-casting triangles (Moller-Trumbore),
// shared by the shadow tests that compare a technique with exact visibility
// (shadow_reference_test.cpp, shadow_volume_test.cpp).
#pragma once

#include "scene/scene.h"

#include <glm/glm.hpp>

#include <array>
#include <cmath>

namespace veil::test::ray_cast {

using Rgb = std::array<double, 3>;

// Transmittance of the scene's shadow-casting triangles along the segment P -> P + t d,
// t in (tMin, tMax): 0 at the first opaque triangle, 1 - alpha + alpha T [McGuire16 Eq. 2] for each
// transparent one.
inline Rgb trianglesTransmittance(const scene::Scene& sc, const glm::dvec3& P, const glm::dvec3& d,
                                  double tMax, double tMin = 1e-6) {
    Rgb T{1.0, 1.0, 1.0};
    for (const auto& object : sc.objects) {
        if (!object.castShadows) continue;
        const scene::Material& m = sc.materials.at(object.material);
        const auto& mesh = sc.meshes.at(object.mesh);
        const glm::dmat4 M(object.transform);
        for (std::size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
            const glm::dvec3 a(M * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[k]]), 1.0));
            const glm::dvec3 b(M *
                               glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[k + 1]]), 1.0));
            const glm::dvec3 c(M *
                               glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[k + 2]]), 1.0));
            const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
            const double det = glm::dot(e1, p);
            if (std::abs(det) < 1e-14) continue;
            const glm::dvec3 s = P - a;
            const double u = glm::dot(s, p) / det;
            if (u < 0.0 || u > 1.0) continue;
            const glm::dvec3 q = glm::cross(s, e1);
            const double v = glm::dot(d, q) / det;
            if (v < 0.0 || u + v > 1.0) continue;
            const double t = glm::dot(e2, q) / det;
            if (t <= tMin || t >= tMax) continue;
            if (!m.isTransparent()) return {0.0, 0.0, 0.0};
            for (int ch = 0; ch < 3; ++ch)
                T[ch] *= 1.0 - m.alpha + m.alpha * m.transmission[ch];
        }
    }
    return T;
}

// Direction from P toward scene light `light` and the distance to it (infinite for a
// directional light).
inline void towardLight(const scene::Light& l, const glm::dvec3& P, glm::dvec3& d, double& tMax) {
    if (l.type == scene::LightType::Directional) {
        d = -glm::normalize(glm::dvec3(l.direction));
        tMax = 1e30;
    } else {
        const glm::dvec3 toLight = glm::dvec3(l.position) - P;
        tMax = glm::length(toLight);
        d = toLight / tMax;
    }
}

// 1 where the segment from P to scene light `light` meets no opaque caster, else 0 (the
// transparent casters are ignored: opaque visibility only). Hits closer than tMin to P are
// ignored: a P unprojected from a float depth buffer lies up to ~1e-4 world units off its
// surface (DEPTH32F at 10 units from a 0.1 near plane), which must not shadow itself.
inline double opaqueVisibility(const scene::Scene& sc, int light, const glm::dvec3& P,
                               double tMin = 1e-6) {
    glm::dvec3 d;
    double tMax;
    towardLight(sc.lights.at(light), P, d, tMax);
    return trianglesTransmittance(sc, P, d, tMax, tMin)[0] > 0.0 ? 1.0 : 0.0;
}

} // namespace veil::test::ray_cast
