#version 450 core
// One direction of the separable Gaussian filter of the moment maps ([Munstermann18 sec. 6]: "filters
// both moment shadow maps with a 9x9 Gaussian"), radius r taps each side, sigma = r / 2, on
// every layer. Moments filter linearly (they are integrals of the depth distribution), which is
// what makes the map filterable; clamped at the map's edges.
#include "../../common/bindings.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray source;
layout(binding = 1, rgba32f) uniform writeonly image2DArray target;

uniform ivec2 direction; // (1, 0) or (0, 1)
uniform int radius;
uniform ivec2 rows; // texel rows [rows.x, rows.y) of this dispatch (moment.cpp, banded runs)

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID) + ivec3(0, rows.x, 0);
    ivec3 size = imageSize(target);
    if (c.x >= size.x || c.y >= rows.y || c.z >= size.z) return;
    float sigma = max(0.5 * float(radius), 0.5);
    vec4 sum = vec4(0.0);
    float weights = 0.0;
    for (int k = -radius; k <= radius; ++k) {
        float w = exp(-0.5 * float(k * k) / (sigma * sigma));
        ivec2 p = clamp(c.xy + k * direction, ivec2(0), size.xy - 1);
        sum += w * texelFetch(source, ivec3(p, c.z), 0);
        weights += w;
    }
    imageStore(target, c, sum / weights);
}
