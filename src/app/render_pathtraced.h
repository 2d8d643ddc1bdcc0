// `veil render scene.json --integrator pathtraced -o x.{exr,png}`: the volumetric path tracer's
// image of the scene's volumes (src/volume/path_tracer.h, properties render.pathtraced.*),
// with the per-pixel standard error beside it (<output stem>-stderr.exr).
#pragma once

#include "scene/scene.h"
#include "volume/path_tracer.h"

#include <filesystem>
#include <string>

namespace veil::app {

// The path tracer's output file and its standard-error file beside it, before any rendering.
std::filesystem::path pathTracedErrorPath(const std::filesystem::path& output);

// Renders and writes; prints what it wrote. `width`/`height` 0 = the scene's.
void renderPathTraced(const scene::Scene& scene, const volume::PathTracerSettings& settings,
                      const std::string& camera, int width, int height,
                      const std::filesystem::path& output, bool progress);

} // namespace veil::app
