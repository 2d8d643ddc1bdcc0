// "veil:light_visibility" of the `stochastic` shadow technique (src/shadows/stochastic):
// the opaque casters' Williams map (opaque_depth.glsl) times the stochastic map's estimate
// of the transparent casters' transmittance, per channel.
//
// [Enderton11 sec. 3.2, Eq. 4]: svis(z) = count(z <= z_i) / S, by percentage-closer filtering: the
// samples of the (2r+1)^2 texels around P whose depth is at or behind the receiver's (minus
// the slope-scaled bias of the opaque map) are unoccluded. Volume samples read the one texel
// under P (S samples): the fog marcher averages many of them per pixel. The grid density
// volumes' optical depth along the light (common/fog_depth.glsl, property `fog`) multiplies
// both: [Enderton11]'s stochastic map holds the surfaces, the media's deep shadow map
// [Lokovic00] their product's other factor (independent attenuation along one light ray).
//
// params[0]: opaque map (bias, PCF radius). params[1]: x = S, y = PCF radius r of the
// stochastic map, z = layers per view L (3: one map per channel, layer v L + c; 1: grey).
#include "../common/opaque_depth.glsl"
#include "../common/fog_depth.glsl"

layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DMSArray stochasticMap;

vec3 stochasticVisibility(int v, vec2 uv, float z, int r) {
    int S = int(shadows.params[1].x);
    int L = int(shadows.params[1].z);
    ivec2 size = ivec2(shadows.mapSize.x);
    ivec2 centre = clamp(ivec2(floor(uv * shadows.mapSize.x)), ivec2(0), size - 1);
    vec3 count = vec3(0.0);
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x) {
            ivec2 t = clamp(centre + ivec2(x, y), ivec2(0), size - 1);
            for (int c = 0; c < L; ++c)
                for (int s = 0; s < S; ++s)
                    count[c] += texelFetch(stochasticMap, ivec3(t, v * L + c), s).r >= z ? 1.0
                                                                                        : 0.0;
        }
    float n = float(2 * r + 1);
    vec3 vis = count / (n * n * float(S));
    return L == 1 ? vec3(vis.x) : vis;
}

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(i, P, v, uv, z)) return;
    float NdotL = saturate(dot(N, L));
    float bias = shadows.params[0].x * (1.0 + 4.0 * (1.0 - NdotL)) / shadowViewDepthScale(v);
    radiance *= opaqueVisibility(i, P, N, L) * shadowFogTransmittance(v, uv, z) *
                stochasticVisibility(v, uv, z - bias, int(shadows.params[1].y));
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(i, P, v, uv, z)) return;
    radiance *= opaqueVisibilityFast(i, P) * shadowFogTransmittance(v, uv, z) *
                stochasticVisibility(v, uv, z - shadows.params[0].x / shadowViewDepthScale(v), 0);
}

#include "../common/visibility_values.glsl"
