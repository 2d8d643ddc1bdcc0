#version 450 core
// Opaque forward pass: Lambert + GGX with Schlick Fresnel, emission, shadowed lights.
// The shaded surface is the one the depth buffer keeps: screen-space shadow techniques
// (`volume`) may answer from the pixel (veil:light_visibility).
#define VEIL_RECEIVER_AT_DEPTH 1
// The receiver-plane shadow slope from this fragment's screen-space derivatives
// (shadows/common/receiver_derivatives.glsl), taken before the discard below.
#define VEIL_RECEIVER_DERIVATIVES 1
// With VEIL_AO (render.ao on) the ambient term is multiplied by the frame's AO buffer, and a
// depth pre-pass runs this program first with depthPrepass set (depth only, no shading).
#include "../common/camera.glsl"
#include "material.glsl"
#include "shading.glsl"

layout(location = 0) out vec4 outColor;

#ifdef VEIL_AO
layout(binding = VEIL_TEX_AO) uniform sampler2D frameAmbientVisibility;
uniform bool depthPrepass;
#endif

void main() {
    shadowReceiverDerivatives(vWorldPos);
    // A binary-coverage material [McGuire17 sec. 6]: only its alpha = 1 interior is opaque.
    if (binaryCoverage && surfaceCoverage() < 1.0) discard;
    vec3 V = viewVector(vWorldPos);
    vec3 N = facingNormal(V);
#ifdef VEIL_AO
    if (depthPrepass) return;
    float ao = texelFetch(frameAmbientVisibility, ivec2(gl_FragCoord.xy), 0).r;
    outColor = vec4(shadeSurfaceOccluded(currentMaterial(), vWorldPos, N, V, 1.0, ao), 1.0);
#else
    outColor = vec4(shadeSurface(currentMaterial(), vWorldPos, N, V, 1.0), 1.0);
#endif
}
