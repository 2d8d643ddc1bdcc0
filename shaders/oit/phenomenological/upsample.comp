#version 450 core
// OIT `phenomenological`, [McGuire16 sec. 5 "Upsample"]: joint-bilateral upsampling of the
// low-resolution particle accumulation "as if the buffers were simply colors", keyed on depth,
// composited into the full-resolution buffers with the accumulation's own operators
// (A, D^2, delta sums add; beta multiplies: the paper's RT1 blend (ZERO, SRC_COLOR)).
// Filter: a tent over the 4 x 4 nearest low-resolution texels (radius 1.75 texels: 7 full-
// resolution pixels at 1/4 resolution, the paper's 7 x 7 tent) times a depth weight
// 1 / (1 + (|dz| / 0.02 z)^2) ([McGuire17 Listing 2] uses a hyperbolic one; this falls off faster
// across silhouettes), normalized. The upsampled contribution is then scaled
// by a confidence, the best depth weight among the taps, so a pixel whose depth matches none
// of the keys (a near opaque edge amid far blocks) receives nothing instead of a leak, while a
// pixel with any matching neighbour takes its value from the matching ones.
#include "../../common/camera.glsl"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = VEIL_PHEN_TEX_DEPTH) uniform sampler2D phenFullDepth;
layout(binding = VEIL_PHEN_TEX_A) uniform sampler2D lowA;
layout(binding = VEIL_PHEN_TEX_BD) uniform sampler2D lowBD;
layout(binding = VEIL_PHEN_TEX_DELTA) uniform sampler2D lowDelta;
layout(binding = VEIL_PHEN_TEX_BKG) uniform sampler2D lowDepth; // downsample_depth.comp
layout(binding = 0, rgba16f) uniform image2D fullA;
layout(binding = 1, rgba16) uniform image2D fullBD;
#ifdef PHEN_REFRACTION
layout(binding = 2, rg16f) uniform image2D fullDelta; // none without refraction
#endif

uniform int phenScale;

float viewDepthOf(float d) {
    mat4 P = camera.projection;
    float ndc = 2.0 * d - 1.0;
    return -(P[3][2] - ndc * P[3][3]) / (ndc * P[2][3] - P[2][2]);
}

void main() {
    ivec2 size = imageSize(fullA);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    ivec2 lowSize = textureSize(lowA, 0);
    float z = viewDepthOf(texelFetch(phenFullDepth, p, 0).r);
    vec2 u = (vec2(p) + 0.5) / float(phenScale) - 0.5; // position in low-res texel centers
    ivec2 base = ivec2(floor(u)) - 1;
    const float radius = 1.75;
    vec4 A = vec4(0.0), BD = vec4(0.0), delta = vec4(0.0);
    float weightSum = 0.0, confidence = 0.0;
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            ivec2 q = base + ivec2(i, j);
            vec2 d = abs(vec2(q) - u);
            float tent = max(0.0, 1.0 - d.x / radius) * max(0.0, 1.0 - d.y / radius);
            if (tent <= 0.0) continue;
            q = clamp(q, ivec2(0), lowSize - 1);
            float zq = viewDepthOf(texelFetch(lowDepth, q, 0).r);
            float rel = abs(z - zq) / (0.02 * max(z, 1e-6));
            float wd = 1.0 / (1.0 + rel * rel);
            float w = tent * wd;
            confidence = max(confidence, wd);
            A += w * texelFetch(lowA, q, 0);
            BD += w * texelFetch(lowBD, q, 0);
#ifdef PHEN_REFRACTION
            delta += w * texelFetch(lowDelta, q, 0);
#endif
            weightSum += w;
        }
    }
    if (weightSum <= 0.0) return;
    A *= confidence / weightSum;
    BD /= weightSum;
    delta *= confidence / weightSum;
    if (all(greaterThanEqual(BD.rgb, vec3(1.0))) && A == vec4(0.0)) return;
    imageStore(fullA, p, imageLoad(fullA, p) + A);
    vec4 full = imageLoad(fullBD, p);
    imageStore(fullBD, p, vec4(full.rgb * mix(vec3(1.0), BD.rgb, confidence),
                               full.a + confidence * BD.a));
#ifdef PHEN_REFRACTION
    imageStore(fullDelta, p, imageLoad(fullDelta, p) + delta);
#endif
}
