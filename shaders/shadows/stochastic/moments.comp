#version 450 core
// `stochastic-vsm`: one view's stochastic MSAA map (L layers, one per channel) to the first
// two moments per texel, E[z] and E[z^2] over its S samples ([McGuire16 sec. 4.3]: "convert the shadow
// maps to Variance Shadow Maps"; the box filter of the samples, [Enderton11 sec. 4.1]).
#include "../../common/bindings.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_SHADOW3) uniform sampler2DMSArray stochasticMap;
layout(binding = VEIL_IMG_OUTPUT, rg32f) uniform writeonly image2DArray moments;

uniform int samples;
uniform int firstLayer; // this view's first layer of the moments array
uniform ivec2 rows; // texel rows [rows.x, rows.y) of this dispatch (stochastic.cpp, bands)

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID) + ivec3(0, rows.x, 0);
    ivec2 size = imageSize(moments).xy;
    if (p.x >= size.x || p.y >= rows.y) return;
    vec2 m = vec2(0.0);
    for (int s = 0; s < samples; ++s) {
        float z = texelFetch(stochasticMap, p, s).r;
        m += vec2(z, z * z);
    }
    imageStore(moments, ivec3(p.xy, firstLayer + p.z), vec4(m / float(samples), 0.0, 0.0));
}
