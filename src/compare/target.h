// What `veil render --compare-to X` compares the frame with: another OIT technique of the
// same frame (a technique id), the same frame with another shadow technique (`shadows:ID`,
// e.g. shadows:reference, at the frame's map size), a stored image (a path: anything with '/' or
// '.', e.g. ref.exr), `cpu`: the fog's double-precision CPU reference (the "fog-march"
// integrator, src/integrators/cpu_reference.h) composited over the scene's background, for
// scenes with volumes, or `pathtraced`: the volumetric path tracer
// (src/integrators/path_tracer.h) with render.pathtraced.*.
#pragma once

#include "base/image.h"
#include "integrators/path_tracer.h"
#include "scene/scene.h"

#include <functional>

#include <string>

namespace veil::compare {

struct CompareTarget {
    enum class Kind { None, Technique, Shadows, File, Cpu, PathTraced };
    Kind kind = Kind::None;
    std::string text;
    std::string shadows; // Kind::Shadows: the shadow technique id
};

CompareTarget parseCompareTarget(const std::string& text);

// Checks before any rendering: the file exists and is a readable image, or the scene has
// volumes for `cpu` (throws veil::Error naming the file or scene). Techniques are checked by
// the caller against the registry.
void checkCompareTarget(const CompareTarget& target, const scene::Scene& scene);

// The stored image (RGB of its first channels), refused with both sizes when it is not
// width x height.
ImageF loadReferenceImage(const CompareTarget& target, int width, int height);

// The fog's double-precision CPU reference (integrators/cpu_reference.h) seen from `camera` with
// `steps` march steps, over the scene's background: per pixel L + T * background, with L the
// single-scattered radiance and T the transmittance along the camera ray. Nothing but fog is
// in it (no surfaces). RGB.
ImageF cpuFogOverBackground(const scene::Scene& scene, const scene::Camera& camera, int width,
                            int height, int steps);

// The CPU fog reference of the frame (the "fog-march" integrator, integrators/registry.h): per
// pixel L + T * background, with L the single-scattered radiance and T the transmittance along
// the camera ray (render.fog_steps steps, at least 256).
// Surfaces are not part of it (cpu_reference.h): `note` says so when the scene has objects.
ImageF cpuFogReference(const scene::Scene& scene, const std::string& camera, int width, int height,
                       std::string& note);

// The path tracer's settings: the scene's "render": {"pathtraced": {...}} as loaded (after the
// overrides, --set render.pathtraced.spp=16), validated against volume::pathTracerSchema();
// defaults for a scene without the block.
volume::PathTracerSettings pathTracedSettings(const scene::Scene& scene);

// The volumetric path tracer's image of the scene's volumes: per pixel the mean radiance
// (background included) and its standard error. `progress(samplesSoFar, spp)` after each pass.
// Surfaces are not part of it: `note` says so when the scene has objects.
volume::PathTracedImage pathTracedReference(const scene::Scene& scene,
                                            const volume::PathTracerSettings& settings,
                                            const std::string& camera, int width, int height,
                                            std::string& note,
                                            const std::function<void(int, int)>& progress = {});

} // namespace veil::compare
