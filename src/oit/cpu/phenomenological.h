// CPU double-precision model of OIT `phenomenological` [McGuire16, McGuire17] for one pixel without
// refraction or diffusion: the accumulation of A ([McGuire16 Eq. 4] with the Eq. 5 weights) and
// beta (Eq. 2), then the resolve of Eq. 3 with self-modulation ([McGuire17 Eq. 14], [McGuire17
// Listing 3] epsilons). The GPU technique must reproduce it to float16 precision; how far the model
// is from the exact sorted composite is what the GL tests measure.
#pragma once

#include <glm/glm.hpp>

#include <span>

namespace veil::oit::cpu {

struct PhenomenologicalLayer {
    double windowDepth = 0.5;     // f = gl_FragCoord.z of [McGuire16 Eq. 5], in [0,1]
    glm::dvec3 radiance{0.0};     // alpha * L_r (reflected + emitted)
    double alpha = 1.0;           // coverage
    glm::dvec3 transmission{0.0}; // t
};

struct PhenomenologicalOptions {
    double weightMin = 0.01; // [McGuire16 Eq. 5] clamp
    double weightMax = 30.0;
    bool selfModulation = true;
};

// Result over `background` for layers in any order (the model is order independent).
glm::dvec3 phenomenologicalResolve(std::span<const PhenomenologicalLayer> layers,
                                   const glm::dvec3& background,
                                   const PhenomenologicalOptions& options = {});

} // namespace veil::oit::cpu
