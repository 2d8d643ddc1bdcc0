#version 450 core
// Opaque forward pass: Lambert + GGX with Schlick Fresnel, emission, shadowed lights.
// The shaded surface is the one the depth buffer keeps: screen-space shadow techniques
// (`volume`) may answer from the pixel (veil:light_visibility).
#define VEIL_RECEIVER_AT_DEPTH 1
#include "../common/camera.glsl"
#include "material.glsl"
#include "shading.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    vec3 V = viewVector(vWorldPos);
    vec3 N = facingNormal(V);
    outColor = vec4(shadeSurface(currentMaterial(), vWorldPos, N, V, 1.0), 1.0);
}
