// Stochastic transparency [Enderton11], three
// registry ids, one class parameterized by variant (stochastic.cpp has the parameter block):
//   stochastic        basic screen-door with stratified S-choose-R masks [Enderton11 sec. 3.1, 3.5]
//   stochastic-alpha  basic + alpha correction by total alpha ([Enderton11 sec. 3.3, 3.5] "basic
//   algorithm
//                     with alpha correction")
//   stochastic-depth  depth-based: total alpha, stochastic depth, accumulation ([Enderton11
//   sec. 3.4, 3.5]
//                     "final antialiased depth-based algorithm")
#pragma once

#include "oit/technique.h"

#include <cstdint>

namespace veil::oit {

enum class StochasticMode { Basic, AlphaCorrected, DepthBased };

struct StochasticParams {
    // MSAA samples per pixel per pass, S. Clamped to GL_MAX_SAMPLES (and the colour/depth
    // texture sample limits and 32) of the driver: llvmpipe 4, NVIDIA 8 and more.
    int samples = 8;
    // Passes with different seeds; total samples per pixel = S x passes [Enderton11 sec. 5].
    int passes = 1;
};

// The properties `samples` and `passes` of the three ids map onto StochasticParams (see the
// parameter block of stochastic.cpp).
// The effective S for the current GL context: min(requested, driver limits, 32).
int stochasticEffectiveSamples(int requested);

void registerStochastic(Registry& registry);

} // namespace veil::oit
