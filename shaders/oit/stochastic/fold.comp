#version 450 core
// Basic and alpha-corrected variants, after each stochastic colour pass: adds the box-filtered
// ([Enderton11 sec. 4.1], operator F) sample average (F(B), F(B1)) of the winner-take-all MSAA buffer
// to a single-sample RGBA32F sum over the repeated passes ([Enderton11 sec. 5]: "average together
// multiple passes with different random seeds"; footnote 4: average B and B1 separately).
#include "../../common/bindings.h"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_OIT0 + 1) uniform sampler2DMS stochColor;
layout(binding = VEIL_IMG_OUTPUT, rgba32f) uniform image2D passSum;

uniform int samples;

void main() {
    ivec2 size = imageSize(passSum);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    vec4 sum = vec4(0.0);
    for (int s = 0; s < samples; ++s) sum += texelFetch(stochColor, p, s);
    imageStore(passSum, p, imageLoad(passSum, p) + sum / float(samples));
}
