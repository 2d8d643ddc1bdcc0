// CPU reference of the fog marcher, in double precision over the same openvdb::FloatGrid:
// transmittance and single-scattered radiance along camera rays, with the lighting model of
// shaders/volume/fog_march.comp (Henyey-Greenstein phase, albedo, emission with the volumes'
// emission and temperature grids (read here from their files, volume/emission.h), ambient, the
// multiple-scattering octaves of render.fog_octaves, spot cone
// and 1/d^2 falloff, transmittance toward each light marched exactly through the density).
// What it leaves out: opaque occluders (no shadow map) and surfaces; tests use scenes where
// those do not matter. Lights other than the GPU's primary light are not self-shadowed on the
// GPU: the reference self-shadows only the primary light too, so both compute one model.
#pragma once

#include "base/image.h"
#include "scene/scene.h"
#include "volume/neighbourhood.h"
#include "volume/path_tracer.h"

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
    // Transmittance from p toward light i (through volumes and homogeneous fog).
    double transmittanceToLight(const glm::dvec3& p, int light, int steps = 256) const;

private:
    struct Volume {
        const scene::VolumeRef* ref;
        openvdb::FloatGrid::ConstPtr grid;
        glm::dmat4 worldToObject;
        glm::dvec3 lo, hi;                            // world bounds
        std::vector<openvdb::FloatGrid::Ptr> channel; // emission / temperature grid(s), or none
        NeighbourhoodMean neighbourhood;              // render.fog_octave_radius > 0 only
    };
    double densityOf(const Volume& v, const glm::dvec3& world) const;
    // render.fog_octave_radius x the neighbourhood mean extinction at a world point.
    double localDepth(const glm::dvec3& world) const;
    glm::dvec3 channelOf(const Volume& v, const glm::dvec3& world) const;
    bool interval(const glm::dvec3& ro, const glm::dvec3& rd, double& t0, double& t1) const;

    const scene::Scene& scene_;
    std::vector<Volume> volumes_;
    double globalDensity_ = 0.0;
    glm::dvec3 globalAlbedo_{0.0};
    double globalAnisotropy_ = 0.0;
    int primaryLight_ = -1;
    ScatteredLight scattered_; // render.fog_scattered_light: the same bake as the GPU's
};

} // namespace veil::volume
