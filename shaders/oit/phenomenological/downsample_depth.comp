#version 450 core
// OIT `phenomenological`, reduced-resolution particles: the key depth of each low-resolution
// texel is the farthest opaque window depth of its s x s block, so particles in front of any
// part of the block are accumulated; the joint-bilateral upsample (upsample.comp) keeps them
// off the nearer opaque pixels of the block.
#include "../../common/bindings.h"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = VEIL_PHEN_TEX_DEPTH) uniform sampler2D phenFullDepth;
layout(binding = VEIL_IMG_OUTPUT, r32f) uniform writeonly image2D lowDepth;

uniform int phenScale; // 2 or 4

void main() {
    ivec2 q;
    if (!regionPixel(imageSize(lowDepth), q)) return;
    ivec2 size = textureSize(phenFullDepth, 0);
    float d = 0.0;
    for (int y = 0; y < phenScale; ++y)
        for (int x = 0; x < phenScale; ++x)
            d = max(d, texelFetch(phenFullDepth, min(q * phenScale + ivec2(x, y), size - 1), 0).r);
    imageStore(lowDepth, q, vec4(d));
}
