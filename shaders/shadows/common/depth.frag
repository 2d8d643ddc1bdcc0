#version 450 core
// Opaque casters into a light view (frame/mesh.vert with the view's matrix): the linear depth
// along the view's axis, normalized to its [near, far] (views.glsl), instead of the projective
// depth, whose precision near a spot light's near plane leaves a world-space bias useless.
#include "views.glsl"

uniform int shadowView;
in vec3 vWorldPos;

void main() { gl_FragDepth = clamp(shadowViewDepth(shadowView, vWorldPos), 0.0, 1.0); }
