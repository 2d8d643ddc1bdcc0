#version 450 core
// AO step 1: camera-space z (view distance) of the opaque depth buffer, level 0 of the
// pyramid the estimator samples (McGuire, Mara & Luebke, Scalable Ambient Obscurance, HPG
// 2012, section 2: linear z once, then a MIP hierarchy). Nothing drawn (depth 1) = far.
#include "ao_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_DEPTH) uniform sampler2D frameDepth;
layout(binding = VEIL_IMG_OUTPUT, r32f) uniform writeonly image2D csz;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(csz)))) return;
    imageStore(csz, p, vec4(aoViewDistance(texelFetch(frameDepth, p, 0).r)));
}
