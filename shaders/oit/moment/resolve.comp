#version 450 core
// Resolve of `moment-*` [Munstermann18 sec. 3.4, Eq. 2]: renormalized compositing over the opaque
// image,  L = T_rgb * L_opaque + (1 - exp(-b_0)) / sum(w) * sum(radiance * T),
// with T_rgb = exp(-b_0,rgb) the colored total transmittance (see emit.glsl). Where the weights
// vanish (no absorbing surface: purely emissive or fully transmitting ones) the sum is added
// unnormalized, as then T = 1 exactly.
#include "../../common/bindings.h"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_OIT0 + 0) uniform sampler2D momentTex0;
layout(binding = VEIL_TEX_OIT0 + 3) uniform sampler2D accumTex;
layout(binding = VEIL_IMG_OUTPUT, rgba16f) uniform image2D hdrImage;

void main() {
    ivec2 size = imageSize(hdrImage);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    vec4 t0 = texelFetch(momentTex0, p, 0);
    vec4 acc = texelFetch(accumTex, p, 0);
    if (t0.x <= 0.0 && all(equal(t0.yzw, vec3(0.0))) && all(equal(acc, vec4(0.0)))) return;
    float b0 = t0.x;
    // 1 - exp(-b0) without cancellation for small b0.
    float coverage = b0 < 1e-3 ? b0 * (1.0 - 0.5 * b0) : 1.0 - exp(-b0);
    float scale = acc.a > 1e-12 ? coverage / acc.a : 1.0;
    vec3 opaque = imageLoad(hdrImage, p).rgb;
    vec3 result = exp(-t0.yzw) * opaque + scale * acc.rgb;
    imageStore(hdrImage, p, vec4(result, 1.0));
}
