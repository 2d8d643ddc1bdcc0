#version 450 core
// AO step 2: level m + 1 of the z pyramid keeps one texel of each 2x2 block of level m,
// chosen on a rotated grid (SAO section 2.2: a sample, not an average, so no false depths
// appear at silhouettes; the rotation keeps the choice from aliasing along one axis).
#include "ao_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_AO_INPUT) uniform sampler2D cszPyramid; // read at level aoLevel
layout(binding = VEIL_IMG_OUTPUT, r32f) uniform writeonly image2D cszNext; // level aoLevel + 1
uniform int aoLevel;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(cszNext)))) return;
    ivec2 q = p * 2 + ivec2((p.y & 1) ^ 1, (p.x & 1) ^ 1);
    q = min(q, textureSize(cszPyramid, aoLevel) - 1);
    imageStore(cszNext, p, vec4(texelFetch(cszPyramid, q, aoLevel).r));
}
