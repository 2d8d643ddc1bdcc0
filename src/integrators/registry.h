// The CPU integrators of the volumes by name (base/named_registry.h, as the OIT and shadow
// techniques are): "fog-march", the fog marcher's double-precision reference (cpu_reference.h),
// and "pathtraced", the volumetric path tracer (path_tracer.h). Each renders the scene's volumes
// over its background (surfaces are in neither) through the medium of medium.h, with the
// properties it declares (render.pathtraced.* for the path tracer, read from the scene).
#pragma once

#include "base/image.h"
#include "base/named_registry.h"
#include "base/properties.h"
#include "scene/scene.h"

#include <functional>
#include <string>

namespace veil::volume {

struct IntegratorImage {
    ImageF radiance;      // RGB: per pixel L + T x background
    ImageF standardError; // RGB: the per-pixel standard error of a Monte Carlo mean; empty else
    int samples = 0;      // per pixel (1 for a deterministic integrator)
};

// `progress(samplesSoFar)` after each pass of a progressive integrator; false stops it early.
using IntegratorProgress = std::function<bool(int)>;

struct IntegratorInfo {
    std::string name;
    std::string description;
    PropertySchema properties; // where the scene keeps them: see the description
    // Loads the grids of the scene's volumes (grid/density_grid.h loadVolume()) and renders
    // them from `camera` at width x height. Throws veil::Error for a scene the integrator cannot
    // render or bad properties (naming their place in the scene).
    std::function<IntegratorImage(const scene::Scene& scene, const scene::Camera& camera, int width,
                                  int height, const IntegratorProgress& progress)>
        render;
};

class IntegratorRegistry : public NamedRegistry<IntegratorInfo> {
public:
    IntegratorRegistry() : NamedRegistry("integrator") {}
    static IntegratorRegistry& instance();
};

} // namespace veil::volume
