// Stochastic shadow maps of the transparent casters, two techniques with one implementation:
//
// `stochastic` [Enderton11 sec. 3.2, 3.6]: every view's transparent casters are drawn from the
// light
//   into an S-sample MSAA depth array, each fragment covering a stratified random subset of
//   R = floor(rho S + xi) samples (gl_SampleMask) with rho = alpha (1 - t) per channel; the
//   receivers count the samples behind them [Enderton11 Eq. 4] over a (2r+1)^2-texel PCF kernel.
//   Coloured transmission: one map per channel (the colored stochastic shadow maps [McGuire16] sec.
//   4.3 builds on), the three channels drawn from common random numbers so their masks nest.
//
// `stochastic-vsm` [McGuire16 sec. 4.3]: the same maps, with the opaque casters drawn into them
// first
//   and the caustic density of [McGuire16 Eq. 10-12], converted to variance shadow maps (the
//   moments z, z^2 over each texel's samples), blurred by a separable tent filter and read with one
//   bilinear tap and Chebyshev's bound (light-bleeding reduction by the usual linstep).
//
// Both multiply in the opaque casters' Williams map (DepthMaps, [McGuire16 sec. 4.3]: "a separate
// traditional Williams shadow map for opaque shadows").
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

void registerStochastic(Registry& registry);

// The blur radius in texels of a `size`^2 map for a `blur_radius` given in texels of a 2048^2
// map (G3D's default 5): the same world-space width at every map size.
int stochasticVsmBlurTexels(int blurRadius, int size);

} // namespace veil::shadows
