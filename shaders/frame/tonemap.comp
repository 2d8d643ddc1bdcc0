#version 450 core
// Tone mapping (compute: no rasterizer needed). Exposure, then either the
// ACES filmic fit of [Narkowicz16], f(x) = x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), per
// channel, or a plain clamp; then the sRGB transfer function (IEC 61966-2-1).
#include "../common/bindings.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_HDR) uniform sampler2D hdrImage;
layout(binding = VEIL_IMG_OUTPUT, rgba8) uniform writeonly image2D ldrImage;

uniform float exposure;
uniform int operatorId; // 0 = ACES fit, 1 = clamp

vec3 acesFit(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 srgbEncode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// The pixels of this dispatch, [x0, y0) .. [x1, y1): the whole frame or one tile of the
// viewer's tiled refinement (Renderer::beginRefinement).
uniform ivec4 region;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy) + region.xy;
    ivec2 size = textureSize(hdrImage, 0);
    if (p.x >= min(size.x, region.z) || p.y >= min(size.y, region.w)) return;
    vec3 c = max(texelFetch(hdrImage, p, 0).rgb, vec3(0.0)) * exposure;
    c = operatorId == 0 ? acesFit(c) : clamp(c, 0.0, 1.0);
    imageStore(ldrImage, p, vec4(srgbEncode(c), 1.0));
}
