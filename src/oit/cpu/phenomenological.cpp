#include "oit/cpu/phenomenological.h"

#include <algorithm>

namespace veil::oit::cpu {

glm::dvec3 phenomenologicalResolve(std::span<const PhenomenologicalLayer> layers,
                                   const glm::dvec3& background,
                                   const PhenomenologicalOptions& options) {
    glm::dvec3 beta(1.0), A(0.0);
    double Aa = 0.0;
    for (const PhenomenologicalLayer& l : layers) {
        const double tMean = (l.transmission.x + l.transmission.y + l.transmission.z) / 3.0;
        const double netCoverage = l.alpha * (1.0 - tMean);
        // [McGuire16 Eq. 5]
        const double tmp = 10.0 * (1.0 - 0.99 * l.windowDepth) * netCoverage;
        const double w = std::clamp(tmp * tmp * tmp, options.weightMin, options.weightMax);
        beta *= glm::dvec3(1.0 - l.alpha) + l.alpha * l.transmission; // [McGuire16 Eq. 2]
        A += w * l.radiance;                                          // [McGuire16 Eq. 4]
        Aa += w * netCoverage;
    }
    glm::dvec3 U = A / std::max(Aa, 1e-5);
    if (options.selfModulation) {
        // [McGuire17 Eq. 14] with the epsilons of [McGuire17 Listing 3].
        const double betaMax = std::max({beta.x, beta.y, beta.z});
        U *= glm::dvec3(0.5) + glm::max(beta, glm::dvec3(1e-3)) / std::max(2e-3, 2.0 * betaMax);
    }
    return background * beta + (glm::dvec3(1.0) - beta) * U; // [McGuire16 Eq. 3]
}

} // namespace veil::oit::cpu
