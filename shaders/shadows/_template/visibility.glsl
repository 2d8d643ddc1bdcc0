// TEMPLATE "veil:light_visibility" of a new shadow technique (src/shadows/_template/template.h):
// defines the transmittance toward light i that every receiver applies to the radiance
// arriving from it, with the same contract for every technique:
//   lightAttenuate(i, P, N, L, radiance)   a surface point P (normal N, direction to the
//                                          light L): multiply radiance by the visibility
//   lightAttenuateInMedium(i, P, radiance) a fog sample P (no normal)
// Leave the radiance untouched where the light is unoccluded, and include
// visibility_values.glsl at the end for the value forms lightVisibility*().
//
// This one scales the opaque casters' shadow ([Williams78] depth maps with PCF,
// common/opaque_depth.glsl) by a property:
// params[0]: x = bias (world units along the light axis), y = PCF radius r;
// params[1]: x = strength, the fraction of the light an opaque caster blocks.
#include "../common/opaque_depth.glsl"

float templateStrength() { return shadows.params[1].x; }

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (shadowLightHasMap(i))
        radiance *= 1.0 - templateStrength() * (1.0 - opaqueVisibility(i, P, N, L));
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (shadowLightHasMap(i))
        radiance *= 1.0 - templateStrength() * (1.0 - opaqueVisibilityFast(i, P));
}

#include "../common/visibility_values.glsl"
