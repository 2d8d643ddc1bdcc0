#version 450 core
// Shadow volumes (src/shadows/volume): the depth pre-pass (world vertices, transform.comp) and
// the volumes' triangles (silhouette.comp) through one expression with an invariant
// gl_Position. A front cap is a copy of its face's world vec4 (w = 1), so the pre-pass and the
// cap give the same depth bits; extruded points have w = 0 (to infinity) or 1.
#include "../../common/camera.glsl"

layout(location = VEIL_ATTR_POSITION) in vec4 inPoint;
invariant gl_Position;

void main() { gl_Position = camera.viewProjection * inPoint; }
