// `veil render scene.json --integrator NAME -o x.{exr,png}`: a CPU integrator's image of the
// scene's volumes (src/integrators/registry.h: "pathtraced", the volumetric path tracer with
// render.pathtraced.*; "fog-march", the fog marcher's reference), and for a Monte Carlo
// integrator <output stem>-stderr.exr with the per-pixel standard error of its mean.
#pragma once

#include "scene/scene.h"

#include <filesystem>
#include <string>

namespace veil::app {

// <output stem>-stderr.exr beside the output.
std::filesystem::path standardErrorPath(const std::filesystem::path& output);

// The path tracer first estimates its time (a timed sample through up to 64 pixels, scaled
// to spp x pixels over the threads) and refuses work past `timeLimit` seconds (0: no limit),
// naming the estimate and how to go on; each pass measures again, and --progress shows
// "spp k/N" with the time left.
constexpr double kDefaultIntegratorTimeLimit = 3600.0;
void renderWithIntegrator(const scene::Scene& scene, const std::string& integrator,
                          const std::string& camera, int width, int height,
                          const std::filesystem::path& output, bool progress,
                          double timeLimit = kDefaultIntegratorTimeLimit);

} // namespace veil::app
