// "veil:light_visibility" of the `moment` shadow technique (src/shadows/moment/moment.h):
// opaque casters through the Williams map with PCF (opaque_depth.glsl), transparent casters
// and density volumes through the absorbance moment maps [Munstermann18 sec. 6], multiplied: "we
// assume that the latter transmittance is constant within the filter region. Under this
// assumption, the appropriate combination operator is simple multiplication" [Munstermann18 sec. 6].
//
// params[0]: opaque map (bias, PCF radius), z = overestimation beta of the media's moments.
// params[1]: x = moment bias alpha, y = overestimation beta, z = 1 for 16-bit storage, w =
// receiver depth offset toward the light (world units: a transparent receiver does not shadow
// itself).
#include "../common/opaque_depth.glsl"
#include "reconstruct.glsl"
#include "../../common/moment_quantize.glsl"

layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray momentAbsorbanceMap; // a_rgb, media
layout(binding = VEIL_TEX_SHADOW2) uniform sampler2DArray momentMomentsMap; // surfaces: a z^k
layout(binding = VEIL_TEX_SHADOW3) uniform sampler2DArray momentMediaMap;   // media: a z^k

// The filtered moments at uv: b0 = (surfaces r, g, b, media), surface and media moments.
// 16-bit storage: the four texels of the bilinear footprint with the normalization undone
// per texel before the interpolation (quantize.comp), so only unnormalized moments are
// filtered, as [Munstermann18 sec. 6] requires.
void momentFetch(int v, vec2 uv, out vec4 b0, out vec4 bs, out vec4 bm) {
    if (shadows.params[1].z < 0.5) {
        b0 = texture(momentAbsorbanceMap, vec3(uv, float(v)));
        bs = texture(momentMomentsMap, vec3(uv, float(v)));
        bm = texture(momentMediaMap, vec3(uv, float(v)));
        return;
    }
    vec2 size = vec2(shadows.mapSize.x);
    vec2 st = uv * size - 0.5;
    ivec2 i0 = ivec2(floor(st));
    vec2 f = st - vec2(i0);
    b0 = vec4(0.0);
    bs = vec4(0.0);
    bm = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec3 p = ivec3(clamp(i0 + o, ivec2(0), ivec2(size) - 1), v);
        float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        // Texel centres through texture(): exact values (texelFetch read zeros in the fog
        // marcher's compute program on llvmpipe 15).
        vec3 c = vec3((vec2(p.xy) + 0.5) / size, float(v));
        vec4 t0 = texture(momentAbsorbanceMap, c);
        b0 += w * t0;
        bs += w * (t0.r + t0.g + t0.b) / 3.0 * momentDequantize4(texture(momentMomentsMap, c));
        bm += w * t0.a * momentDequantize4(texture(momentMediaMap, c));
    }
}

// Fraction of one moment set's absorbance (total `total`, moments `b`) in front of zf, with
// overestimation weight `beta`.
float momentFront(float total, vec4 b, float zf, float beta) {
    if (!(total > 1e-7)) return 0.0; // [Munstermann18 sec. 3.2]: nothing absorbs here
    // Bias toward the power-4 vector of docs/oit.md#moment-constants (float32 or 16-bit storage).
    vec4 biasVector = shadows.params[1].z > 0.5 ? vec4(0.0, 0.628, 0.0, 0.628)
                                                 : vec4(0.0, 0.375, 0.0, 0.375);
    return shadowMomentFraction(mix(b / total, biasVector, shadows.params[1].x), zf, beta);
}

// Transmittance (rgb) of the transparent casters and media between the light and normalized
// depth `depth` in view v.
vec3 momentTransmittance(int v, vec2 uv, float depth) {
    vec4 b0, bs, bm;
    momentFetch(v, uv, b0, bs, bm);
    float zf = clamp(depth, 0.0, 1.0) * 2.0 - 1.0;
    // Surfaces: the depth distribution of their mean absorbance scales each channel's total
    // (src/shadows/moment/moment.h, "Colour"); media: grey, their own moments and their own
    // beta (a continuous absorbance: beta = 0, the lower bound, is systematically light).
    float surfaces = (b0.r + b0.g + b0.b) / 3.0;
    vec3 absorbance = momentFront(surfaces, bs, zf, shadows.params[1].y) * b0.rgb +
                      momentFront(b0.a, bm, zf, shadows.params[0].z) * b0.a;
    return exp(-absorbance);
}


vec3 momentVisibility(int i, vec3 P) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(i, P, v, uv, z)) return vec3(1.0);
    return momentTransmittance(v, uv, z - shadows.params[1].w / shadowViewDepthScale(v));
}

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
    radiance *= opaqueVisibility(i, P, N, L) * momentVisibility(i, P);
}

// Samples of the fog marcher: the maps hold the volumes' own absorbance too, so this is the
// fog's self-shadowing as well (the technique's attenuatesMedia()).
void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
    radiance *= opaqueVisibilityFast(i, P) * momentVisibility(i, P);
}

#include "../common/visibility_values.glsl"
