#version 450 core
// Opaque forward pass: Lambert + GGX with Schlick Fresnel, emission, shadowed lights.
#include "../common/camera.glsl"
#include "material.glsl"
#include "shading.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    vec3 V = viewVector(vWorldPos);
    vec3 N = facingNormal(V);
    outColor = vec4(shadeSurface(currentMaterial(), vWorldPos, N, V, 1.0), 1.0);
}
