#version 450 core
// Hands the marched fog of this pixel to the active OIT technique as one full-screen fragment
// (techniques whose perPixelEmit() is Fragments: the contribution is fog_contribution.glsl's).
#include "../common/camera.glsl"

#include "veil:oit_emit"

#include "fog_contribution.glsl"

void main() {
    vec4 L, T;
    if (!fogContribution(ivec2(gl_FragCoord.xy), L, T)) discard;
    gl_FragDepth = fogWindowDepth(L.a);
    oitEmit(oitFragment(L.rgb, 1.0, T.rgb, L.a)); // no surface, no particle
}
