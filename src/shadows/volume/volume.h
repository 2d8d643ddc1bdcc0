// `volume`: stencil shadow volumes of the opaque casters (depth-fail, caps, extrusion to
// infinity with depth clamping), one screen-space visibility layer per shadowed light, with
// the culling and clamping of [Eisemann06 sec. 3.2] driven by the light's slice map of the
// receivers the camera sees (src/shadows/volume/volume.cpp has the passes).
//
// The volumes are built in compute (src/shadows/volume/geometry.h: world vertices and the
// casters' adjacency; shaders/shadows/volume/silhouette.comp) and drawn indirectly; culled
// casters are never launched, clamped volumes close with a silhouette fan, and casters whose
// volume cannot hold the eye are counted depth-pass without caps.
//
// Properties: size, max_lights, bias, pcf_radius (the opaque map: transparent receivers and
// fog samples, and the occluders of caster culling), caster_culling, receiver_culling,
// clamping ([Eisemann06 sec. 3.2], each on by default), zpass (true), grid (columns per side of the
// light's slice map, 256), slices (128), measure (stencil fill, volume triangles and pipeline
// statistics per frame, true), timing (GL_TIMESTAMP per part, false).
#pragma once

#include "shadows/technique.h"

namespace veil::shadows {

void registerVolume(Registry& registry);

} // namespace veil::shadows
