// "veil:light_visibility" of the `shadow_map` technique (DESIGN.md "Passes, properties,
// resources"): transmittance from a world point toward light i, as a colour, for surfaces and
// for samples in a medium. Opaque casters only: 1 or 0 (PCF-filtered) per light; lights
// without a shadow map are unoccluded.
#include "shadow_map.glsl"

// A surface point with normal N, L toward the light (slope-scaled bias, PCF).
vec3 lightVisibility(int i, vec3 P, vec3 N, vec3 L) {
    if (lighting.lights[i].directionShadow.w < 0.5) return vec3(1.0);
    return vec3(shadowVisibility(P, N, L));
}

// A point inside a participating medium (no normal): the fog marcher's samples.
vec3 lightVisibilityInMedium(int i, vec3 P) {
    if (lighting.lights[i].directionShadow.w < 0.5) return vec3(1.0);
    return vec3(shadowVisibilityFast(P));
}
