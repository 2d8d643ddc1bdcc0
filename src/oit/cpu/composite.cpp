#include "oit/cpu/composite.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>

namespace veil::oit::cpu {

namespace {
bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
} // namespace

Fragment makeFragment(double depth, const glm::dvec3& radiance, double alpha,
                      const glm::dvec3& transmission) {
    VEIL_CHECK(std::isfinite(depth) && finite(radiance), "fragment depth/radiance must be finite");
    VEIL_CHECK(alpha >= 0.0 && alpha <= 1.0, "fragment alpha {} outside [0, 1]", alpha);
    for (int c = 0; c < 3; ++c)
        VEIL_CHECK(transmission[c] >= 0.0 && transmission[c] <= 1.0,
                   "fragment transmission[{}] = {} outside [0, 1]", c, transmission[c]);
    Fragment f;
    f.depth = depth;
    f.premultipliedRadiance = alpha * radiance;
    f.modulation = glm::dvec3(1.0 - alpha) + alpha * transmission; // [McGuire16 Eq. 2]
    return f;
}

glm::dvec3 compositeInOrder(const std::vector<Fragment>& fragments, const glm::dvec3& background) {
    glm::dvec3 color(0.0), throughput(1.0);
    for (const Fragment& f : fragments) {
        color += throughput * f.premultipliedRadiance; // [Enderton11 Eq. 2]
        throughput *= f.modulation;
    }
    return color + throughput * background;
}

glm::dvec3 compositeSorted(const std::vector<Fragment>& fragments, const glm::dvec3& background) {
    std::vector<Fragment> sorted = fragments;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const Fragment& a, const Fragment& b) { return a.depth < b.depth; });
    return compositeInOrder(sorted, background);
}

glm::dvec3 netModulation(const std::vector<Fragment>& fragments) {
    glm::dvec3 m(1.0);
    for (const Fragment& f : fragments)
        m *= f.modulation;
    return m;
}

} // namespace veil::oit::cpu
