// Exact sorted compositing in double precision: the CPU reference every OIT technique is
// ultimately compared against (no GL).
//
// A fragment contributes its premultiplied radiance alpha * L_r and modulates everything
// behind it per channel by m = 1 - alpha + alpha * T [McGuire16 Eq. 1 and 2]. Sorted front to back
// ([Enderton11 Eq. 2], generalised to colored transmission):
//     C = sum_i (prod_{j<i} m_j) * c_i + (prod_j m_j) * background.
#pragma once

#include <glm/glm.hpp>

#include <vector>

namespace veil::oit::cpu {

struct Fragment {
    double depth = 0.0;                    // distance along the view axis (smaller = nearer)
    glm::dvec3 premultipliedRadiance{0.0}; // alpha * L_r
    glm::dvec3 modulation{1.0};            // 1 - alpha + alpha * T [McGuire16 Eq. 2]
};

// A surface of coverage `alpha`, reflected/emitted radiance `radiance` (not premultiplied)
// and transmission `transmission` at view depth `depth`. Throws veil::Error for alpha
// outside [0, 1], T outside [0, 1]^3 or non-finite values.
Fragment makeFragment(double depth, const glm::dvec3& radiance, double alpha,
                      const glm::dvec3& transmission = glm::dvec3(0.0));

// The exact composite: stable sort by depth (equal depths keep their given order), then
// front-to-back accumulation over `background`. The input is not modified.
glm::dvec3 compositeSorted(const std::vector<Fragment>& fragments, const glm::dvec3& background);

// Front-to-back accumulation in the order given (no sort): what `blend` computes when the
// fragments arrive in reverse of this order.
glm::dvec3 compositeInOrder(const std::vector<Fragment>& fragments, const glm::dvec3& background);

// Net modulation of the background, prod_i m_i ([McGuire16 Eq. 2]: order independent).
glm::dvec3 netModulation(const std::vector<Fragment>& fragments);

} // namespace veil::oit::cpu
