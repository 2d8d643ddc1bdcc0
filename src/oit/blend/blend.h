// `blend`: unsorted alpha blending (see shaders/oit/blend/emit.glsl). Composites directly
// into the HDR target in submission order; no resolve, no storage of its own.
#pragma once

#include "oit/technique.h"

namespace veil::oit {

void registerBlend(Registry& registry);

} // namespace veil::oit
