#version 450 core
// OIT `wboit` resolve ([McGuire16 Listing 2] without refraction, diffusion and self-modulation):
//     result = background * r + (1 - r) * A.rgb / max(A.a, 1e-5)          [McGuire16 Eq. 3, 4]
// with the under-/overflow guards of [McGuire16 Listing 2] on the RGBA16F accumulation.
#include "../../common/bindings.h"
#include "../../common/math.glsl"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_OIT0) uniform sampler2D accumTex;
layout(binding = VEIL_TEX_OIT0 + 1) uniform sampler2D revealageTex;
layout(binding = VEIL_IMG_OIT_WBOIT_TARGET, rgba16f) uniform restrict image2D hdrImage;

void main() {
    ivec2 size = imageSize(hdrImage);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    float r = texelFetch(revealageTex, p, 0).r;
    if (r >= 1.0) return; // no transparency [McGuire16 Listing 2]
    vec4 A = texelFetch(accumTex, p, 0);
    // [McGuire16 Listing 2]: suppress under- and overflow.
    if (isinf(A.a)) A.a = maxComponent(A.rgb);
    if (isinf(maxComponent(A.rgb))) A = vec4(isinf(A.a) ? 1.0 : A.a);
    vec4 background = imageLoad(hdrImage, p);
    vec3 result = background.rgb * r + (1.0 - r) * A.rgb / max(A.a, 0.00001);
    imageStore(hdrImage, p, vec4(result, background.a));
}
