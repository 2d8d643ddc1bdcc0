#version 450 core
// AO step 4: separable depth-aware (bilateral) blur of the raw obscurance (SAO section 2.3),
// one axis per dispatch: taps t = -R..R at `aoStride` pixels, Gaussian weight
// exp(-t^2 / (2 (R/2)^2)) times max(0, 1 - sharpness |z_t - z_C| / z_C), so that the blur does
// not cross depth edges. Far pixels (nothing drawn) keep 1.
#include "ao_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_AO_INPUT) uniform sampler2D cszPyramid;
layout(binding = VEIL_TEX_AO_INPUT + 1) uniform sampler2D aoSource;
layout(binding = VEIL_IMG_OUTPUT, r16f) uniform writeonly image2D aoTarget;

uniform ivec2 aoAxis; // (1, 0) or (0, 1)
uniform int aoBlurRadius;
uniform int aoStride;
uniform float aoSharpness;

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(aoSource, 0);
    if (any(greaterThanEqual(c, size))) return;
    float zC = texelFetch(cszPyramid, c, 0).r;
    float center = texelFetch(aoSource, c, 0).r;
    if (zC >= camera.viewport.w * 0.999) {
        imageStore(aoTarget, c, vec4(center));
        return;
    }
    float sigma = 0.5 * float(aoBlurRadius);
    float sum = 0.0, wsum = 0.0;
    for (int t = -aoBlurRadius; t <= aoBlurRadius; ++t) {
        ivec2 q = clamp(c + aoAxis * (t * aoStride), ivec2(0), size - 1);
        float z = texelFetch(cszPyramid, q, 0).r;
        float w = exp(-float(t * t) / (2.0 * sigma * sigma)) *
                  max(0.0, 1.0 - aoSharpness * abs(z - zC) / zC);
        sum += w * texelFetch(aoSource, q, 0).r;
        wsum += w;
    }
    imageStore(aoTarget, c, vec4(sum / wsum)); // t = 0 has weight 1: wsum >= 1
}
