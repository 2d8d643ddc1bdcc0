// `wboit`: weighted blended OIT (McGuire & Bavoil 2013) as used by 000 section 4.2, with the
// depth weight of 000 Eq. 5 and the resolve guards of 000 Listing 2
// (shaders/oit/wboit/emit.glsl, resolve.comp).
//
// Parameters (fixed, from the paper):
//   weight   w = clamp([10 (1 - 0.99 gl_FragCoord.z) alpha (1 - mean T)]^3, 0.01, 30)  000 Eq. 5
//   targets  RT0 accumulation RGBA16F (000 Table 2), RT1 revealage R16F (R8 underflows after
//            a few dozen low-alpha layers; 000 appendix notes beta underflow)
//   T        scalar: net coverage alpha (1 - mean T) as in 000 Listing 1 (grey modulation)
// Storage: 8 + 2 = 10 bytes per pixel.
#pragma once

#include "oit/technique.h"

namespace veil::oit {

void registerWboit(Registry& registry);

} // namespace veil::oit
