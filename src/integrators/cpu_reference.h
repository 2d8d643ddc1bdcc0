// CPU reference of the fog marcher (the "fog-march" integrator, registry.h), in double precision
// over the same openvdb::FloatGrid: transmittance and single-scattered radiance along camera rays
// through the medium of medium.h, with the lighting model of shaders/volume/fog_march.comp
// (Henyey-Greenstein phase, albedo, emission with the volumes' emission and temperature grids,
// ambient, the multiple-scattering octaves of render.fog_octaves, spot cone and 1/d^2 falloff,
// transmittance toward each light marched exactly through the density).
// What it leaves out: opaque occluders (no shadow map) and surfaces; tests use scenes where
// those do not matter. Lights other than the GPU's primary light are not self-shadowed on the
// GPU: the reference self-shadows only the primary light too, so both compute one model.
#pragma once

#include "base/image.h"
#include "grid/neighbourhood.h"
#include "integrators/medium.h"
#include "integrators/path_tracer.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <vector>

namespace veil::volume {

struct FogSample {
    glm::dvec3 radiance{0.0};
    double transmittance = 1.0;
};

class CpuFogReference {
public:
    // `grids` holds the grid of every non-homogeneous volume of `scene`, in scene order. The
    // emission channels the volumes name are loaded here (throws veil::Error as
    // loadEmissionChannel()).
    CpuFogReference(const scene::Scene& scene, std::vector<openvdb::FloatGrid::ConstPtr> grids);

    // Extinction coefficient at a world point (sum over volumes and homogeneous fog).
    double extinction(const glm::dvec3& world) const;
    // The camera ray through image position (px, py) in pixels (row 0 = top) of a width x
    // height image, from the near plane to `maxDistance` beyond it (default: the far plane).
    FogSample pixel(const scene::Camera& camera, int width, int height, double px, double py,
                    int steps, double maxDistance = -1.0) const;
    // Every pixel (TBB-parallel). RGBA: rgb radiance, a transmittance.
    ImageF render(const scene::Camera& camera, int width, int height, int steps) const;
    // render() over the scene's background: RGB, per pixel L + T x render.background.
    ImageF renderOverBackground(const scene::Camera& camera, int width, int height,
                                int steps) const;
    // Transmittance from p toward light i (through volumes and homogeneous fog).
    double transmittanceToLight(const glm::dvec3& p, int light, int steps = 256) const;

private:
    double transmittanceToLight(Medium::Lookup& lookup, const glm::dvec3& p, int light,
                                int steps) const;
    // render.fog_octave_radius x the neighbourhood mean extinction at a world point.
    double localDepth(const glm::dvec3& world) const;

    const scene::Scene& scene_;
    Medium medium_;
    // Per volume of the medium, with render.fog_octave_radius > 0 only (else empty).
    std::vector<NeighbourhoodMean> neighbourhood_;
    int primaryLight_ = -1;
    ScatteredLight scattered_; // render.fog_scattered_light: the same bake as the GPU's
};

} // namespace veil::volume
