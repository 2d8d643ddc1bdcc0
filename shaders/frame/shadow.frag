#version 450 core
// Shadow map: stores linear depth along the light axis, normalized to the fitted near/far
// range, instead of the projective depth (whose precision for a spot light with a near plane
// close to the light leaves a world-space bias useless).
#include "../shadows/shadow_map/shadow_map.glsl"

in vec3 vWorldPos;

void main() { gl_FragDepth = clamp(shadowLinearDepth(vWorldPos), 0.0, 1.0); }
