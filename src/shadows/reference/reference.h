// `reference`: exact light visibility at the maps' texel resolution, for tests and
// `--compare-to` (issue: shadows from everything that is not opaque, item 5).
//   opaque casters   the shared depth map (common/depth_maps.h); pcf_radius 0 by default: a
//                    hard test at the texel's depth
//   transparent      every fragment of every transparent caster of every light view in a
//                    per-texel list (a node pool linked from a head image per layer); a
//                    receiver multiplies the transmittance 1 - alpha + alpha T [McGuire16 Eq. 2] of
//                    each fragment of its texel in front of it. The product is order-
//                    independent, so unlike the OIT `reference` nothing is sorted.
//   density volumes  the optical depth marched from the receiver to the light (to the volumes'
//                    exit for a directional light) in media_steps midpoint steps, per receiver
//                    and per fog sample (slow by design; attenuatesMedia() is true).
// A pool too small for the frame's fragments is grown and the pass redone in the same frame
// (stats: fragments, capacity, regrown).
//
// Properties: size, max_lights, bias, pcf_radius (0), media_steps (256), receiver_offset
// (0.02 world units toward the light: a transparent receiver does not shadow itself),
// max_list (4096 fragments read per texel at most), initial_pool (nodes, grown as needed).
// The CPU double-precision ray caster it is checked against is tests/gl/ray_cast_shadows.h.
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

void registerReference(Registry& registry);

} // namespace veil::shadows
