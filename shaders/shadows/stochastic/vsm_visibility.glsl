// "veil:light_visibility" of the `stochastic-vsm` shadow technique (src/shadows/stochastic):
// the opaque casters' Williams map (opaque_depth.glsl) times the variance shadow map of the
// caustic colored stochastic shadow map [McGuire16 sec. 4.3], per channel: one bilinear tap of the
// blurred moments (E[z], E[z^2]) and Chebyshev's one-sided bound
//     p = sigma^2 / (sigma^2 + (z - mu)^2)  for z > mu, else 1
// [Donnelly06], with the light-bleeding reduction linstep(amount, 1, p).
// The map holds the opaque casters too, so for a receiver behind one transparent plane of
// density rho the texel's samples are {plane: rho, receiver: 1 - rho} and p = 1 - rho exactly.
// No depth bias: the variance floor sigma_min = bias / depth scale (the opaque map's world
// bias in map units) absorbs the receiver's own depth and its slope within a texel.
//
// params[0]: opaque map (bias, PCF radius). params[1]: x = light-bleeding amount, y = layers
// per view L (3: one map per channel, layer v L + c; 1: grey), z = 1 when fog samples read the
// VSM too (property fog_reads_vsm; off by default: on llvmpipe the fog marcher's fetches of
// this array return zeros in most invocations, seen 2026-12-01, so fog gets the opaque map).
// With `fog`, surfaces and fog samples alike also get the grid density volumes' optical depth
// along the light (common/fog_depth.glsl), an R32F volume the marcher reads correctly.
#include "../common/opaque_depth.glsl"
#include "../common/fog_depth.glsl"

layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray vsmMap;

float vsmChebyshev(vec2 m, float z, float minVariance, float bleeding) {
    if (z <= m.x) return 1.0;
    float variance = max(m.y - m.x * m.x, minVariance);
    float d = z - m.x;
    float p = variance / (variance + d * d);
    return clamp((p - bleeding) / (1.0 - bleeding), 0.0, 1.0); // linstep(bleeding, 1, p)
}

// Bilinear tap by four texelFetch (the same weights as GL_LINEAR).
vec2 vsmMoments(int layer, vec2 uv) {
    ivec2 size = ivec2(shadows.mapSize.x);
    vec2 t = uv * shadows.mapSize.x - 0.5;
    ivec2 i0 = ivec2(floor(t));
    vec2 f = t - vec2(i0);
    ivec2 a = clamp(i0, ivec2(0), size - 1), b = clamp(i0 + 1, ivec2(0), size - 1);
    vec2 m00 = texelFetch(vsmMap, ivec3(a.x, a.y, layer), 0).rg;
    vec2 m10 = texelFetch(vsmMap, ivec3(b.x, a.y, layer), 0).rg;
    vec2 m01 = texelFetch(vsmMap, ivec3(a.x, b.y, layer), 0).rg;
    vec2 m11 = texelFetch(vsmMap, ivec3(b.x, b.y, layer), 0).rg;
    return mix(mix(m00, m10, f.x), mix(m01, m11, f.x), f.y);
}

float vsmChannel(int layer, vec2 uv, float z, float minVariance) {
    return vsmChebyshev(vsmMoments(layer, uv), z, minVariance, shadows.params[1].x);
}

// The fog's transmittance toward light i at P (common/fog_depth.glsl; 1 without `fog`).
float vsmFog(int i, vec3 P) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(i, P, v, uv, z)) return 1.0;
    return shadowFogTransmittance(v, uv, z);
}

vec3 vsmVisibility(int i, vec3 P) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(i, P, v, uv, z)) return vec3(1.0);
    int L = int(shadows.params[1].y);
    float sigma = shadows.params[0].x / shadowViewDepthScale(v);
    float m = sigma * sigma;
    if (L == 1) return vec3(vsmChannel(v, uv, z, m));
    return vec3(vsmChannel(3 * v, uv, z, m), vsmChannel(3 * v + 1, uv, z, m),
                vsmChannel(3 * v + 2, uv, z, m));
}

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (shadowLightHasMap(i))
        radiance *= opaqueVisibility(i, P, N, L) * vsmFog(i, P) * vsmVisibility(i, P);
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
    radiance *= opaqueVisibilityFast(i, P) * vsmFog(i, P);
    if (shadows.params[1].z > 0.5) radiance *= vsmVisibility(i, P);
}

#include "../common/visibility_values.glsl"
