// Monte Carlo volumetric path tracer in double precision (the "pathtraced" integrator,
// registry.h): the reference the fog marcher's single and multiple scattering are measured
// against (docs/volumes.md "Path-traced reference").
//
// Light transport in the scene's density volumes (the medium of medium.h, as the CPU fog
// reference's, cpu_reference.h), from the same camera rays (pixel centres):
//   - free paths by delta (Woodcock) tracking against local majorants [Woodcock65; Novak18]:
//     a majorant grid (majorant_grid.h) of cells of 4 voxels of the finest grid over the
//     volumes' box, each the sum over volumes of density_scale x the largest voxel trilinear
//     samples in it read (from the dense copy of dense_grid.h; the leaf nodes' largest values
//     where it has none), walked cell by cell by a DDA that spends an exponential optical depth
//     over them (empty cells are crossed at once); with PathTracerSettings::localMajorants off,
//     one cell: the sum over volumes of density_scale x the grid's largest value (the same
//     estimator with more null collisions, the tracer's before local majorants);
//   - at a real collision the volume is chosen in proportion to its extinction, the path weight
//     is multiplied by its albedo (RGB) and a direction is drawn from its Henyey-Greenstein
//     phase function [Henyey41] by inverting its CDF;
//   - next-event estimation toward every light at every scattering event, the transmittance by
//     ratio tracking [Novak14 sec. 4] against the same majorants (unbiased, with Russian
//     roulette below 0.1);
//   - a path that leaves the volumes after at least one scattering event sees the ambient
//     radiance render.ambient from every direction (a uniform sky); leaving before any, the
//     background render.background;
//   - emission (radiance per unit length: volume `emission` x density, or the emission or
//     blackbody temperature grid of emission.h, loaded by the medium) by the null-collision
//     estimator: weight x emission / majorant at every tentative collision (a volume with an
//     emission grid keeps 1/20 of the one global majorant in its box's cells, where its
//     density may be 0 and it still emits);
//   - at most max_bounces scattering events (1 = single scattering), Russian roulette on the
//     path weight from roulette_depth on.
// Every sample's random numbers come from a PCG32 stream [ONeill14] keyed by (seed, pixel,
// sample index), so an image is the same for every thread count and a progressive run of
// 2 x n samples continues the one of n. Pixels are rendered in TBB parallel passes of
// `batch` samples each; the per-pixel standard error of the mean comes with the image.
// Not modelled: surfaces (objects are ignored, as in the CPU fog reference) and the global
// "homogeneous" fog (it fills all space, so a path never leaves it: refused).
#pragma once

#include "base/image.h"
#include "base/properties.h"
#include "integrators/dense_grid.h"
#include "integrators/majorant_grid.h"
#include "integrators/medium.h"
#include "integrators/pcg32.h"
#include "scene/scene.h"

#include <openvdb/openvdb.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace veil::volume {

struct PathTracerSettings {
    int spp = 256;
    int maxBounces = 256;
    std::uint32_t seed = 1;
    int rouletteDepth = 8;
    int batch = 16; // samples per pixel per progressive pass
    // Delta and ratio tracking against the majorant grid's cells; off: one majorant for all
    // space (the estimator before local majorants, kept to compare with).
    bool localMajorants = true;
};

// render.pathtraced.* (spp, max_bounces, seed, roulette_depth, batch).
const PropertySchema& pathTracerSchema();
PathTracerSettings pathTracerSettings(const Properties& properties);
// The scene's render.pathtraced (RenderSettings::pathtracedProperties) validated against the
// schema; throws veil::Error naming the value's place in the scene file.
PathTracerSettings pathTracerSettings(const scene::Scene& scene);

struct PathTracedImage {
    ImageF radiance;      // RGB: L + (path reached the background) x background
    ImageF standardError; // RGB: per-pixel standard error of the mean
    int samples = 0;
};

// A 1-D slab for validation: thickness `tau` (optical), homogeneous extinction 1, isotropic
// (g = 0) or Henyey-Greenstein scattering, light entering at the top at normal incidence, no
// refractive-index mismatch. Uses the tracer's own collision sampling (with a majorant of
// `majorantFactor` x the extinction, so null collisions are exercised), phase sampling and
// roulette.
struct SlabTally {
    double reflectance = 0.0, reflectanceError = 0.0;                   // diffuse
    double diffuseTransmittance = 0.0, diffuseTransmittanceError = 0.0; // >= 1 scattering
    double directTransmittance = 0.0, directTransmittanceError = 0.0;   // unscattered
};
SlabTally traceSlab(double tau, double albedo, double g, std::uint64_t paths, std::uint32_t seed,
                    double majorantFactor = 2.0);

// The light arriving at points of a grid over the volumes' bounds after at least one
// scattering event, or from the sky (render.ambient) without one: what the fog marcher adds to
// its single scattering with render.fog_scattered_light (docs/scattered-light.md). Per texel, from
// `samples` paths traced from its centre in uniform random directions (the path tracer's own
// transport: delta tracking, next-event estimation, roulette, emission), the first two
// spherical-harmonic bands of the arriving radiance (P1): the mean radiance over directions (RGB)
// and G = 3 x mean(L_Y w), w the light's travel direction, so that L(w) ~ mean + G . w (luminance
// Y). Convolved with Henyey-Greenstein(g) toward direction V this is mean x (1 + g G . V / mean_Y):
// HG's first Legendre coefficient is g.
struct ScatteredLight {
    glm::dvec3 lo{0.0}, hi{0.0}; // world box; texel i's centre at lo + (i + 0.5) / dims x (hi - lo)
    glm::ivec3 dims{0};
    std::vector<glm::vec4> mean; // rgb: mean arriving radiance, a: its luminance
    std::vector<glm::vec4> flux; // xyz: G (luminance), w: 0
    int samples = 0;
    // Trilinear between texel centres, clamped to the edge texels (as GL_CLAMP_TO_EDGE): the
    // in-scattered radiance toward direction `toEye` for phase anisotropy g, per unit sigma_s.
    glm::dvec3 inscattered(const glm::dvec3& world, const glm::dvec3& toEye, double g) const;
};

// The smallest world-space voxel edge of the scene's grid volumes (`grids` in scene order,
// without homogeneous fog), with each volume's transform; 1e300 without grids.
double finestVoxelSize(const scene::Scene& scene,
                       const std::vector<openvdb::FloatGrid::ConstPtr>& grids);

// The cache's grid for `scene` over [lo, hi]: render.fog_scattered_light_cell voxels of the
// finest grid per texel, at most kScatteredLightMaxTexels per axis, at least 2.
constexpr int kScatteredLightMaxTexels = 128;
glm::ivec3 scatteredLightDims(const scene::Scene& scene,
                              const std::vector<openvdb::FloatGrid::ConstPtr>& grids,
                              const glm::dvec3& lo, const glm::dvec3& hi);

// The texels of the cache's grid (`dims` over [lo, hi]) that surfaces read with a small
// footprint, where the bake's noise would show on them (docs/scattered-light.md "Surfaces lit by
// the cache"): those whose cell, grown by one texel on every side, overlaps the world bounds of a
// triangle of an object of `scene` (of the whole object for billboard meshes). Sorted indices,
// x fastest, and the paths they trace: render.fog_scattered_light_samples times
// render.fog_scattered_light_surface_factor, less where that would more than double the bake
// (at most as many more paths as all texels trace). Empty where the factor is 1.
struct ScatteredLightSurface {
    std::vector<std::uint32_t> texels;
    int samples = 0;
};
ScatteredLightSurface scatteredLightSurfaceTexels(const scene::Scene& scene, const glm::dvec3& lo,
                                                  const glm::dvec3& hi, const glm::ivec3& dims);

class VolumePathTracer {
public:
    // `grids` holds the grid of every volume of `scene`, in scene order (as CpuFogReference;
    // the medium of medium.h, without homogeneous fog).
    VolumePathTracer(const scene::Scene& scene, std::vector<openvdb::FloatGrid::ConstPtr> grids,
                     PathTracerSettings settings);

    // One radiance sample through image position (px, py) (pixels, row 0 at the top).
    glm::dvec3 sample(const scene::Camera& camera, int width, int height, double px, double py,
                      std::uint64_t pixel, std::uint32_t index) const;

    // settings.spp samples per pixel in passes of settings.batch; after each pass
    // `progress(samplesSoFar)` is called and may return false to stop early.
    PathTracedImage render(const scene::Camera& camera, int width, int height,
                           const std::function<bool(int)>& progress = {}) const;

    // The largest extinction anywhere (the sum over volumes of density_scale x the grid's
    // largest value) and the local majorants tracking uses.
    double majorant() const { return majorant_; }
    const MajorantGrid& majorants() const { return majorants_; }

    // The scattered-light cache (ScatteredLight above) on a dims grid over [lo, hi] (TBB over
    // texels; each texel's random numbers are keyed by (settings.seed, texel, sample), so it
    // does not depend on the thread count). `progress(fraction of texels done)` is called now
    // and then, from any thread.
    // The texels listed in `surfaceTexels` (sorted) trace `surfaceSamples` paths instead (more:
    // their first `samples` are those of the others; scatteredLightSurfaceTexels()).
    ScatteredLight scatteredLight(const glm::dvec3& lo, const glm::dvec3& hi,
                                  const glm::ivec3& dims, int samples,
                                  const std::function<void(double)>& progress = {},
                                  const std::vector<std::uint32_t>& surfaceTexels = {},
                                  int surfaceSamples = 0) const;
    // The irradiance at world point `p` of a surface with unit normal `n` from the volumes'
    // emission and scattered light and from the sky (render.ambient) seen through them, without
    // the lights' unscattered light: what the surfaces lit by the scattered-light cache receive
    // from it (docs/scattered-light.md "Surfaces lit by the cache"), the reference they are tested
    // against. `samples` cosine-weighted directions about n, each traced as the cache's paths
    // are (the same transport; escaping, a path sees the sky; no surface blocks it); E = pi x
    // their mean radiance, with its standard error in `standardError` when given. The random
    // numbers are keyed by (settings.seed, key, sample).
    glm::dvec3 surfaceIrradiance(const glm::dvec3& p, const glm::dvec3& n, int samples,
                                 std::uint64_t key, glm::dvec3* standardError = nullptr) const;
    // The world box of the volumes (the union of their bounds).
    void worldBounds(glm::dvec3& lo, glm::dvec3& hi) const;

private:
    // Extinction and emitted radiance per unit length at a point (summed over the volumes).
    struct Local {
        double sigma = 0.0;
        glm::dvec3 emission{0.0};
    };
    Local localAt(Medium::Lookup& lookup, const glm::dvec3& p,
                  std::vector<double>* perVolume) const;
    void buildMajorants();
    double transmittance(Medium::Lookup& lookup, const glm::dvec3& o, const glm::dvec3& d,
                         double tMax, Pcg32& rng) const;
    // escapeSeesAmbient: a path leaving before any scattering sees render.ambient (the sky),
    // not render.background (a camera ray's).
    glm::dvec3 trace(Medium::Lookup& lookup, glm::dvec3 o, glm::dvec3 d, double tMax, Pcg32& rng,
                     bool escapeSeesAmbient = false) const;

    const scene::Scene& scene_;
    PathTracerSettings settings_;
    Medium medium_;
    double majorant_ = 0.0;
    MajorantGrid majorants_;
    std::vector<DenseGrid> dense_; // per volume: its density as an array (dense_grid.h)
};

} // namespace veil::volume
