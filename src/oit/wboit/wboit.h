// `wboit`: weighted blended OIT [McGuire13] as used by [McGuire16 sec. 4.2], with the
// depth weight of [McGuire16 Eq. 5] and the resolve guards of [McGuire16 Listing 2]
// (shaders/oit/wboit/emit.glsl, resolve.comp).
//
// Parameters (fixed, from the paper):
//   weight   w = clamp([10 (1 - 0.99 gl_FragCoord.z) alpha (1 - mean T)]^3, 0.01, 30)  [McGuire16
//   Eq. 5] targets  RT0 accumulation RGBA16F [McGuire16 Table 2], RT1 revealage R16F (R8 underflows
//   after
//            a few dozen low-alpha layers; [McGuire16] appendix notes beta underflow)
//   T        scalar: net coverage alpha (1 - mean T) as in [McGuire16 Listing 1] (grey modulation)
// Storage: 8 + 2 = 10 bytes per pixel.
#pragma once

#include "oit/technique.h"

namespace veil::oit {

void registerWboit(Registry& registry);

} // namespace veil::oit
