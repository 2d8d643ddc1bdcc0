#version 450 core
// `stochastic-vsm`: one 1D pass of the separable tent filter over the moments ([McGuire16 sec. 4.3]:
// "filter them with a 15x15 tent kernel (in two 1D passes)"): weights r + 1 - |i| for |i| <= r,
// normalized; texels outside the map clamp to the edge. Every layer (view, channel) at once.
#include "../../common/bindings.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_SHADOW2) uniform sampler2DArray source;
layout(binding = VEIL_IMG_OUTPUT, rg32f) uniform writeonly image2DArray target;

uniform int radius;
uniform ivec2 direction; // (1, 0) or (0, 1)
uniform ivec2 rows; // texel rows [rows.x, rows.y) of this dispatch (stochastic.cpp, bands)

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID) + ivec3(0, rows.x, 0);
    ivec2 size = imageSize(target).xy;
    if (p.x >= size.x || p.y >= rows.y) return;
    vec2 sum = vec2(0.0);
    float weights = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        ivec2 q = clamp(p.xy + i * direction, ivec2(0), size - 1);
        float w = float(radius + 1 - abs(i));
        sum += w * texelFetch(source, ivec3(q, p.z), 0).rg;
        weights += w;
    }
    imageStore(target, p, vec4(sum / weights, 0.0, 0.0));
}
