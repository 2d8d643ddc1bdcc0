// The emission of a volume entry (scene.h VolumeRef: emission, emission_grid,
// temperature_grid), as the fog marcher computes it (shaders/volume/fog_medium.glsl
// volumeEmitted()), in double precision with the exact blackbody integral: shared by the CPU
// fog reference and the path tracer.
#pragma once

#include "scene/scene.h"
#include "volume/blackbody.h"
#include "volume/ray_box.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

namespace veil::volume {

// Radiance emitted per unit length at a point of unscaled density `density` where the
// volume's emission channel (its emission or temperature grid, when it names one) is
// `channel`.
inline glm::dvec3 emittedRadiance(const scene::VolumeRef& ref, double density, double channel) {
    const glm::dvec3 emission(ref.emission);
    if (!ref.emissionGrid.empty()) return channel * emission;
    if (ref.temperatureGrid.empty()) return density * emission;
    const double kelvin = double(ref.temperatureScale) * channel + double(ref.temperatureOffset);
    return density * (emission + double(ref.temperatureIntensity) * double(ref.densityScale) *
                                     blackbodyRgb(kelvin));
}

// Widens a volume's world box [lo, hi] to its emission grid's (the emission may reach past the
// density's active voxels; the GPU widens the density's topology the same way).
inline void widenToEmission(const scene::VolumeRef& ref, const openvdb::FloatGrid* channel,
                            glm::dvec3& lo, glm::dvec3& hi) {
    if (!channel || ref.emissionGrid.empty()) return;
    glm::dvec3 a, b;
    gridWorldBox(*channel, ref.transform, a, b);
    lo = glm::min(lo, a);
    hi = glm::max(hi, b);
}

} // namespace veil::volume
