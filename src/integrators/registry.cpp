#include "integrators/registry.h"

#include "integrators/cpu_reference.h"
#include "integrators/medium.h"
#include "integrators/path_tracer.h"

#include <algorithm>
#include <utility>

namespace veil::volume {

namespace {

void registerFogMarch(IntegratorRegistry& registry) {
    registry.add({"fog-march",
                  "the fog marcher's CPU reference (transmittance and single scattering along "
                  "camera rays with the marcher's lighting model: octaves, scattered-light "
                  "cache, emission), render.fog_steps steps per ray (at least 256)",
                  PropertySchema(),
                  [](const scene::Scene& scene, const scene::Camera& camera, int width, int height,
                     const IntegratorProgress& progress) {
                      const CpuFogReference reference(scene, loadMediumGrids(scene));
                      IntegratorImage out;
                      out.radiance = reference.renderOverBackground(
                          camera, width, height, std::max(256, scene.render.fogSteps));
                      out.samples = 1;
                      if (progress) progress(1);
                      return out;
                  }});
}

void registerPathTraced(IntegratorRegistry& registry) {
    registry.add({"pathtraced",
                  "the volumetric path tracer (delta tracking, next-event estimation, "
                  "render.pathtraced.*)",
                  pathTracerSchema(),
                  [](const scene::Scene& scene, const scene::Camera& camera, int width, int height,
                     const IntegratorProgress& progress) {
                      const PathTracerSettings settings = pathTracerSettings(scene);
                      const VolumePathTracer tracer(scene, loadMediumGrids(scene), settings);
                      PathTracedImage image = tracer.render(camera, width, height, progress);
                      return IntegratorImage{std::move(image.radiance),
                                             std::move(image.standardError), image.samples};
                  }});
}

} // namespace

IntegratorRegistry& IntegratorRegistry::instance() {
    static IntegratorRegistry* registry = [] {
        auto* r = new IntegratorRegistry();
        registerFogMarch(*r);
        registerPathTraced(*r);
        return r;
    }();
    return *registry;
}

} // namespace veil::volume
