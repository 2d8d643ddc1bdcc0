// `moment`: moment shadow maps for transparent casters and density volumes ([Munstermann18 sec. 6],
// "the moment-based analog of Fourier opacity mapping"), with the opaque casters in their own
// Williams map ([Munstermann18 sec. 6]: "for opaque shadow casters, any shadow technique may be
// used"; we keep the PCF map every technique shares instead of a 64-bit moment shadow map).
//
// Per light view (src/shadows/views.h), one frame:
//   shadow              opaque casters' depth (common/depth_maps.h)            -> shadow.depth
//   shadow.transparent  transparent casters, additive, no depth test [Munstermann18 sec. 6],
//   caster.frag:
//                       absorbance per channel and 4 power moments of the mean absorbance at
//                       the linear depth z in [-1, 1]                           -> shadow.moments
//   shadow.media        the volumes marched along every texel's ray from the light, each step's
//                       absorbance sigma dt added at its depth (media.comp)     -> shadow.moments
//   shadow.filter       separable Gaussian, radius `blur_radius` (4 = the paper's 9x9)
//   shadow.quantize     only with storage quantized16: 16-bit copy the receivers read
// Receivers (visibility.glsl): opaque PCF x exp(-A(zf)), A from the 4-moment reconstruction
// (reconstruct.glsl), overestimation beta = 0 for shadows [Munstermann18 sec. 7.2].
//
// Colour: three full moment maps (one per channel) would cost 15 floats per texel. Instead
// the transparent surfaces' total absorbance b0 is stored per channel (3 floats) and their
// depth distribution once, as the moments of their mean absorbance; a receiver scales each
// channel's total by the fraction of the mean absorbance in front of it. This is exact for
// any depth order when the surfaces along a texel share one hue and for any hues when the
// receiver is behind all of them (the floor); it mixes hues only for a receiver between two
// surfaces of different colours along one texel. The density volumes are grey and get their
// own b0 and moments (mixing them into the surfaces' mean would dilute a pane's colour in the
// fog shaft under it: the stained-glass test measured R:G of 0.50 instead of 0.33 that way).
// 12 floats per texel, three RGBA32F arrays.
//
// Properties (besides size, max_lights, bias, pcf_radius of the opaque map):
//   moment_bias      alpha, interpolation of the normalized moments toward the power-4 bias
//                    vector (docs/oit.md#moment-constants): 6e-5 (the 16-bit figure; float32 ports
//                    that used 5e-7 met NaN for a single surface)
//   overestimation   beta of [Munstermann18 Algorithm 2]: 0 for shadows [Munstermann18 sec. 7.2]
//   storage          float32 (additive blending only) or quantized16 (half-float b0, UNORM16
//                    normalized moments through the 4-moment transform, after filtering)
//   blur_radius      Gaussian taps each side (sigma = r / 2); 4 = 9x9 as [Munstermann18 sec. 6]
//   media_steps      steps per texel ray through the volumes' bounds
//   receiver_offset  world distance toward the light at which receivers look the maps up (a
//                    transparent receiver does not shadow itself)
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

void registerMoment(Registry& registry);

} // namespace veil::shadows
