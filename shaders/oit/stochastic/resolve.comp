#version 450 core
// Composite of the stochastic techniques over the opaque HDR image ([Enderton11 sec. 3.5 step 5] / basic
// step 4), per pixel with a box filter F over the S samples (and the repeated passes):
//   basic (VARIANT 0):  C = F(B) + F(empty) * background                     [Enderton11 sec. 3.1]
//   alpha (VARIANT 1):  C = bg * prod(1 - a + aT) + alpha_C F(B) / F(B1)      ([Enderton11 sec. 4.1], A)
//   depth (VARIANT 2):  C = bg * prod(1 - a + aT) + alpha_C F(U) / F(U1)      ([Enderton11 sec. 4.2], D)
// with alpha_C = 1 - F(prod(1 - a_eff)) [Enderton11 Eq. 5] from the total-alpha target; the
// background is dimmed per sample and then filtered [Enderton11 sec. 3.5], which for a single-sample
// opaque image is the filtered product.
#include "../../common/bindings.h"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_OIT0 + 0) uniform sampler2DMS totalAlpha;
layout(binding = VEIL_TEX_OIT0 + 1) uniform sampler2DMS accumulation; // depth variant: U, U1
layout(binding = VEIL_TEX_OIT0 + 2) uniform sampler2D passSum;        // basic/alpha: B, B1
layout(binding = VEIL_IMG_OUTPUT, rgba16f) uniform image2D hdrImage;

uniform int variant;
uniform int samples;
uniform int passes;

void main() {
    ivec2 size = imageSize(hdrImage);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    vec4 bg = imageLoad(hdrImage, p);
    vec3 result;
    if (variant == 0) {
        vec4 b = texelFetch(passSum, p, 0) / float(passes); // F(B), F(B1)
        result = b.rgb + (1.0 - b.a) * bg.rgb;
    } else {
        vec4 t = vec4(0.0);
        for (int s = 0; s < samples; ++s) t += texelFetch(totalAlpha, p, s);
        t /= float(samples);
        float alphaC = 1.0 - t.a;
        vec4 c;
        if (variant == 1) {
            c = texelFetch(passSum, p, 0);
        } else {
            c = vec4(0.0);
            for (int s = 0; s < samples; ++s) c += texelFetch(accumulation, p, s);
        }
        // [Enderton11 sec. 4.1/4.2]: the "otherwise 0" case of A and D.
        vec3 corrected = c.a > 0.0 ? alphaC * c.rgb / c.a : vec3(0.0);
        result = bg.rgb * t.rgb + corrected;
    }
    imageStore(hdrImage, p, vec4(result, bg.a));
}
