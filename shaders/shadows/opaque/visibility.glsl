// "veil:light_visibility" of the `opaque` shadow technique (src/shadows/opaque): Williams
// (1978) depth maps of the opaque casters, one layer per light view, PCF over (2r+1)^2 taps
// for surfaces and one hardware-filtered tap for volume samples. Transparent casters and the
// fog cast no shadow here: this is the baseline the other techniques are measured against.
//
// params[0]: x = bias (world units along the light axis, slope-scaled for surfaces), y = PCF
// radius r.
//
// The interface is "attenuate the radiance arriving from light i": receivers call
// lightAttenuate*() on the incident radiance and a technique leaves it untouched where the
// light is unoccluded. On the H200 this form cost nothing over an inlined lookup, where
// multiplying by a returned vec3(1.0) cost 0.8% of the opaque pass and 2.4% of the fog
// (bench/RESULTS.md, 2026-12-01). lightVisibility*() return the value where one is needed.
#include "../common/opaque_depth.glsl"

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (shadowLightHasMap(i)) radiance *= opaqueVisibility(i, P, N, L);
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (shadowLightHasMap(i)) radiance *= opaqueVisibilityFast(i, P);
}

#include "../common/visibility_values.glsl"
