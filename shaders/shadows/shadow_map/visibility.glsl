// "veil:light_visibility" of the `shadow_map` technique (DESIGN.md "Passes, properties,
// resources"): transmittance from a world point toward light i, a colour, for surfaces and for
// samples in a medium. Opaque casters only: 1 or 0 (PCF-filtered) per light; lights without a
// shadow map are unoccluded.
//
// The interface is "attenuate the radiance arriving from light i": receivers call
// lightAttenuate*() on the incident radiance, and a technique leaves it untouched where the
// light is unoccluded. On the H200 this form costs nothing over the inlined shadow lookup,
// where multiplying by a returned vec3(1.0) cost 0.8% of the opaque pass and 2.4% of the fog
// (bench/RESULTS.md, 2026-12-01). lightVisibility*() return the value where one is needed.
#include "shadow_map.glsl"

// A surface point with normal N, L toward the light (slope-scaled bias, PCF).
void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (lighting.lights[i].directionShadow.w > 0.5) radiance *= shadowVisibility(P, N, L);
}

// A point inside a participating medium (no normal): the fog marcher's samples.
void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (lighting.lights[i].directionShadow.w > 0.5) radiance *= shadowVisibilityFast(P);
}

vec3 lightVisibility(int i, vec3 P, vec3 N, vec3 L) {
    vec3 v = vec3(1.0);
    lightAttenuate(i, P, N, L, v);
    return v;
}

vec3 lightVisibilityInMedium(int i, vec3 P) {
    vec3 v = vec3(1.0);
    lightAttenuateInMedium(i, P, v);
    return v;
}
