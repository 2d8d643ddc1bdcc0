#version 450 core
// OIT `phenomenological`, resolve stage ([McGuire16 sec. 5] / [McGuire17 sec. 5]; [McGuire16 Listing 2] /
// [McGuire17 Listing 3]), as a compute shader over a copy of the opaque image:
//   refract  sample the background at the pixel + delta [McGuire16 sec. 5 "Refract"]
//   diffuse  occlusion-aware gather with the disk filter [McGuire16 sec. 5 "Diffuse", Listing 2]
//   combine  U' with self-modulation ([McGuire16 Eq. 13] / [McGuire17 Eq. 14]), then [McGuire16 Eq. 3].
#include "../../common/bindings.h"
#include "../../common/math.glsl"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = VEIL_PHEN_TEX_A) uniform sampler2D phenA;
layout(binding = VEIL_PHEN_TEX_BD) uniform sampler2D phenBD;
layout(binding = VEIL_PHEN_TEX_DELTA) uniform sampler2D phenDelta;
layout(binding = VEIL_PHEN_TEX_BKG) uniform sampler2D phenBackground; // linear filtering
layout(binding = VEIL_IMG_OUTPUT, rgba16f) uniform writeonly image2D hdrOut;

uniform float phenMaxDiffusionPixels; // D^2 is stored divided by its square
uniform bool phenSelfModulation;
uniform bool phenRefraction;
uniform bool phenDiffusion;

float minComponent(vec3 v) { return min(v.x, min(v.y, v.z)); }

void main() {
    ivec2 size = textureSize(phenBD, 0);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    vec4 BD = texelFetch(phenBD, p, 0);
    vec3 B = BD.rgb;
    if (minComponent(B) >= 1.0) return; // no transparency: the opaque image stays

    float dmax2 = phenMaxDiffusionPixels * phenMaxDiffusionPixels;
    float D2 = BD.a * dmax2; // diffusion variance in pixels^2 ([McGuire16 Eq. 7] squared)
    vec4 A = texelFetch(phenA, p, 0);
    // [McGuire16 Listing 2]: suppress under- and overflow of the float16 sums.
    if (isinf(A.a)) A.a = maxComponent(A.rgb);
    if (isinf(maxComponent(A.rgb))) A = vec4(isinf(A.a) ? 1.0 : A.a);
    if (any(isnan(A))) A = vec4(0.0);

    // [McGuire16 Eq. 13] / [McGuire17 Eq. 14] (epsilons of [McGuire17 Listing 3]).
    if (phenSelfModulation) A.rgb *= vec3(0.5) + max(B, vec3(1e-3)) / max(2e-3, 2.0 * maxComponent(B));

    vec2 delta = vec2(0.0);
    if (phenRefraction) {
        // [McGuire17 sec. 4.3.2]: the layers' pixel offsets averaged with the weights c w of their
        // reflected light (emit.glsl): RT2 holds sum c w delta / 64, A_a sum c w.
        vec2 d = texelFetch(phenDelta, p, 0).xy;
        float Aa = texelFetch(phenA, p, 0).a;
        if (Aa > 0.0 && !isinf(Aa) && !any(isinf(d)) && !any(isnan(d))) delta = 64.0 * d / Aa;
    }

    vec3 bkg = vec3(0.0);
    if (phenDiffusion && D2 > 0.0) {
        // [McGuire16 sec. 5 "Diffuse"]: gather from taps q with |q| <= min(D[p], D[p + q]) so that a
        // background less diffused than the distance (e.g. pressed against the glass) does
        // not bleed. (The text prints the inequality the other way round; Listing 2 and this
        // code keep taps inside both radii.)
        ivec2 C = p + ivec2(round(delta));
        const int stride = 2; // tap spacing
        int R = int(min(sqrt(D2), phenMaxDiffusionPixels) / float(stride)) * stride;
        float weightSum = 0.0;
        for (int qx = -R; qx <= R; qx += stride) {
            for (int qy = -R; qy <= R; qy += stride) {
                float radius2 = float(qx * qx + qy * qy);
                if (radius2 > D2) continue;
                ivec2 tap = clamp(C + ivec2(qx, qy), ivec2(0), size - 1);
                float bkgRadius2 = texelFetch(phenBD, tap, 0).a * dmax2;
                if (radius2 > bkgRadius2) continue;
                // Disk filter (Listing 2), its weight normalised by the tap's disk area.
                float w = 1.0 / max(bkgRadius2, 1e-4) + 1e-5;
                bkg += w * texelFetch(phenBackground, tap, 0).rgb;
                weightSum += w;
            }
        }
        bkg /= max(weightSum, 1e-20);
    } else {
        // No diffusion: bilinear sample at the fractional refracted position.
        bkg = textureLod(phenBackground, (vec2(p) + 0.5 + delta) / vec2(size), 0.0).rgb;
    }
    // [McGuire16 Eq. 3] with U' = A_rgb / A_a (Eq. 4), self-modulated.
    vec3 result = bkg * B + (vec3(1.0) - B) * A.rgb / max(A.a, 1e-5);
    // Keep the float16 target finite (a legitimately huge U would otherwise store +inf).
    imageStore(hdrOut, p, vec4(min(result, vec3(65504.0)), 1.0));
}
