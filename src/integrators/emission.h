// The emission of a volume entry (scene.h VolumeRef: emission, emission_grid,
// temperature_grid), as the fog marcher computes it (shaders/volume/fog_medium.glsl
// volumeEmitted()), in double precision with the exact blackbody integral: shared by the CPU
// fog reference and the path tracer.
#pragma once

#include "integrators/blackbody.h"
#include "integrators/ray_box.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <glm/glm.hpp>

#include <vector>

namespace veil::volume {

// Radiance emitted per unit length at a point of unscaled density `density` where the
// volume's emission channel (its emission or temperature grid, when it names one) is
// `channel` (a scalar grid's value in every component; a colour grid's RGB).
inline glm::dvec3 emittedRadiance(const scene::VolumeRef& ref, double density,
                                  const glm::dvec3& channel) {
    const glm::dvec3 emission(ref.emission);
    if (!ref.emissionGrid.empty()) return channel * emission;
    if (ref.temperatureGrid.empty()) return density * emission;
    const double kelvin = double(ref.temperatureScale) * channel.x + double(ref.temperatureOffset);
    return density * (emission + double(ref.temperatureIntensity) * double(ref.densityScale) *
                                     blackbodyRgb(kelvin));
}

// Widens a volume's world box [lo, hi] to its emission grid's (the emission may reach past the
// density's active voxels; the GPU widens the density's topology the same way).
inline void widenToEmission(const scene::VolumeRef& ref,
                            const std::vector<openvdb::FloatGrid::Ptr>& channel, glm::dvec3& lo,
                            glm::dvec3& hi) {
    if (ref.emissionGrid.empty()) return;
    for (const auto& grid : channel) {
        glm::dvec3 a, b;
        gridWorldBox(*grid, ref.transform, a, b);
        lo = glm::min(lo, a);
        hi = glm::max(hi, b);
    }
}

// The channel's value at point `object` (the scene entry's object space):
// trilinear in each grid, a scalar grid's value in every component.
template <typename Accessors>
glm::dvec3 sampleChannel(const std::vector<openvdb::FloatGrid::Ptr>& channel, Accessors& acc,
                         const glm::dvec3& object) {
    glm::dvec3 out(0.0);
    for (std::size_t k = 0; k < channel.size(); ++k)
        out[int(k)] = openvdb::tools::BoxSampler::sample(
            acc[k], channel[k]->worldToIndex(openvdb::Vec3d(object.x, object.y, object.z)));
    return channel.size() == 1 ? glm::dvec3(out.x) : out;
}

} // namespace veil::volume
