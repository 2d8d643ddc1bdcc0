// `opaque`: [Williams78] shadow maps of the opaque casters for every shadow-casting light
// (directional, spot, and point lights through six cube faces), PCF-filtered in the receivers
// (shaders/shadows/opaque/visibility.glsl). Transparent casters and the fog cast no shadow:
// this is the baseline the other shadow techniques are measured against.
//
// Properties: size (texels per view side, 2048), max_lights (4), bias (world-space depth bias
// along the light axis, slope-scaled for surfaces, 0.01), pcf_radius (taps (2r+1)^2, 1),
// receiver_slope (where the receiver plane's slope comes from: derivatives).
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

void registerOpaque(Registry& registry);

// The receiver-side properties every technique's opaque map reads (bias, pcf_radius,
// receiver_slope), for the schemas of techniques that include the opaque map.
PropertySchema& addOpaqueMapProperties(PropertySchema& schema);

// The defines that compile receiver_slope into the receiving programs
// (shaders/shadows/common/opaque_depth.glsl): "VEIL_RECEIVER_SLOPE N", N = 0 derivatives,
// 1 geometric, 2 none, 3 plane-bias; 0 for a technique without the property
// (Technique::receivers).
std::vector<std::string> opaqueMapDefines(const Properties& properties);

} // namespace veil::shadows
