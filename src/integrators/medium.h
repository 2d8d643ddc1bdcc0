// The participating medium of the CPU integrators (the fog-march reference, cpu_reference.h; the
// path tracer, path_tracer.h), built once from a scene and its grids: every density volume with
// its world box (the grid's active voxels with a voxel of margin, widened to its emission grid's)
// and its emission channel (loaded from the volume's file, emission.h), the homogeneous fog
// entries summed into one medium filling all space, trilinear lookups of density and emission
// channel. Beside it the optics both integrators use, written once: the Henyey-Greenstein phase
// function [Henyey41] and its sampling, the light arriving at a point from a scene light (1/d^2,
// the spot cone's smoothstep) and the camera ray through an image position. The model is the fog
// marcher's (shaders/volume/fog_medium.glsl), in double precision.
#pragma once

#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace veil::volume {

// The Henyey-Greenstein phase function (per steradian) of the cosine between the light's travel
// directions before and after scattering, anisotropy g in (-1, 1).
inline double henyeyGreenstein(double cosTheta, double g) {
    const double d = 1.0 + g * g - 2.0 * g * cosTheta;
    return (1.0 - g * g) / (4.0 * std::numbers::pi * d * std::sqrt(d));
}

// That cosine drawn from HG(g) by inverting its CDF with a uniform u in [0, 1) (isotropic for
// |g| < 1e-4).
inline double sampleHenyeyGreensteinCos(double g, double u) {
    if (std::abs(g) < 1e-4) return 1.0 - 2.0 * u;
    const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    return std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

// GLSL's smoothstep: 0 below e0, 1 above e1, a cubic Hermite ramp between.
inline double smoothstep(double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// A scene light seen from a point, before any medium: the unit direction toward it, its distance
// (1e300 for a directional light) and the irradiance it brings (colour x intensity, over d^2 for
// point and spot lights, times the spot's smoothstep between its outer and inner cones).
struct LightArrival {
    glm::dvec3 toLight{0.0};
    double distance = 1e300;
    glm::dvec3 irradiance{0.0};
};
LightArrival lightArrival(const scene::Light& light, const glm::dvec3& p);

// The camera ray through image position (px, py) in pixels (row 0 at the top) of a width x height
// image: from its point on the near plane, unit direction, `length` to the far plane.
struct CameraRay {
    glm::dvec3 origin{0.0}, direction{0.0, 0.0, -1.0};
    double length = 0.0;
};
CameraRay cameraRay(const scene::Camera& camera, int width, int height, double px, double py);

// The grids of `scene`'s volumes as Medium takes them: every volume's but the homogeneous ones,
// in scene order, loaded by grid/density_grid.h loadVolume() (throws veil::Error as it does).
std::vector<openvdb::FloatGrid::ConstPtr> loadMediumGrids(const scene::Scene& scene);

class Medium {
public:
    struct Volume {
        const scene::VolumeRef* ref;
        openvdb::FloatGrid::ConstPtr grid;
        glm::dmat4 worldToObject;
        glm::dvec3 lo, hi;                            // world bounds
        std::vector<openvdb::FloatGrid::Ptr> channel; // emission / temperature grid(s), or none
    };
    // The homogeneous fog entries (procedural "homogeneous") as one medium filling all space:
    // the sum of their density scales, their albedos weighted by it, the last one's anisotropy.
    struct Homogeneous {
        double density = 0.0;
        glm::dvec3 albedo{0.0};
        double anisotropy = 0.0;
    };
    // Accessors of every volume's grids. OpenVDB accessors cache the last node they visited and
    // are not thread-safe: one Lookup per thread (lookup()).
    struct Lookup {
        std::vector<openvdb::FloatGrid::ConstAccessor> density;
        std::vector<std::vector<openvdb::FloatGrid::ConstAccessor>> channel;
    };
    // Unscaled density (trilinear, as stored, negative values included) and emission channel
    // (emission.h sampleChannel()) at a point; both 0 outside the volume's world bounds.
    struct Point {
        double density = 0.0;
        glm::dvec3 channel{0.0};
    };

    // `grids` holds the grid of every volume of `scene` but the homogeneous ones, in scene order.
    // With `allowHomogeneous` false a homogeneous entry is refused (an integrator whose paths
    // must leave the medium). `integrator` names the caller in messages. Loads the emission
    // channels the volumes name (throws veil::Error as loadEmissionChannel()).
    Medium(const scene::Scene& scene, std::vector<openvdb::FloatGrid::ConstPtr> grids,
           const std::string& integrator, bool allowHomogeneous);

    const std::vector<Volume>& volumes() const { return volumes_; }
    const Homogeneous& homogeneous() const { return homogeneous_; }

    Lookup lookup() const;
    double density(Lookup& lookup, std::size_t volume, const glm::dvec3& world) const;
    Point sample(Lookup& lookup, std::size_t volume, const glm::dvec3& world) const;

    // The hull of the intervals in which the ray o + t d crosses the volumes' bounds (ray_box.h);
    // false when it meets none.
    bool interval(const glm::dvec3& o, const glm::dvec3& d, double& t0, double& t1) const;
    // The union of the volumes' world bounds.
    void worldBounds(glm::dvec3& lo, glm::dvec3& hi) const;

private:
    bool outside(const Volume& v, const glm::dvec3& world) const {
        return glm::any(glm::lessThan(world, v.lo)) || glm::any(glm::greaterThan(world, v.hi));
    }

    std::vector<Volume> volumes_;
    Homogeneous homogeneous_;
};

} // namespace veil::volume
