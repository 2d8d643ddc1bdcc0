// The fog's one contribution per pixel, shared by its two emitters into the OIT technique:
// fog_emit.frag (a full-screen fragment) and fog_emit.comp (one invocation per pixel, issue
// 14). Radiance L with coverage 1 and transmission T, at the fog's representative depth
// ([McGuire17 sec. 7.2]: "a single full-screen quad that models ray-marched OIT fog").
// Reduced-resolution fog is upsampled with a joint bilateral filter keyed on the opaque depth
// [McGuire16 sec. 5].
#include "../common/bindings.h"

layout(binding = VEIL_TEX_FOG_RADIANCE) uniform sampler2D fogRadiance;
layout(binding = VEIL_TEX_FOG_TRANSMITTANCE) uniform sampler2D fogTransmittance;
layout(binding = VEIL_TEX_DEPTH) uniform sampler2D opaqueDepth;

uniform int resolutionDivisor;
uniform mat4 invProjection;
uniform mat4 projection;

float viewDepthAt(ivec2 p) {
    ivec2 full = textureSize(opaqueDepth, 0);
    vec2 ndc = (vec2(p) + 0.5) / vec2(full) * 2.0 - 1.0;
    vec4 v = invProjection * vec4(ndc, texelFetch(opaqueDepth, p, 0).r * 2.0 - 1.0, 1.0);
    return -v.z / v.w;
}

// The fog's radiance (rgb; a = representative view depth) and transmittance at full-resolution
// pixel p; false where it contributes nothing (T = 1, no radiance).
bool fogContribution(ivec2 p, out vec4 L, out vec4 T) {
    if (resolutionDivisor == 1) {
        L = texelFetch(fogRadiance, p, 0);
        T = texelFetch(fogTransmittance, p, 0);
    } else {
        // Joint bilateral: bilinear weights of the 4 nearest fog texels times a depth term.
        float z = viewDepthAt(p);
        ivec2 size = textureSize(fogRadiance, 0);
        vec2 f = (vec2(p) + 0.5) / float(resolutionDivisor) - 0.5;
        ivec2 base = ivec2(floor(f));
        vec2 w = f - vec2(base);
        L = vec4(0.0);
        T = vec4(0.0);
        float sum = 0.0, bestDiff = 1e30;
        vec4 bestL = vec4(0.0), bestT = vec4(1.0);
        for (int j = 0; j < 4; ++j) {
            ivec2 o = ivec2(j & 1, j >> 1);
            ivec2 c = clamp(base + o, ivec2(0), size - 1);
            vec4 l = texelFetch(fogRadiance, c, 0), t = texelFetch(fogTransmittance, c, 0);
            float bil = (o.x == 1 ? w.x : 1.0 - w.x) * (o.y == 1 ? w.y : 1.0 - w.y);
            float diff = abs(t.a - z);
            float wd = bil * exp(-diff / max(0.02 * z, 1e-4));
            L += wd * l;
            T += wd * t;
            sum += wd;
            if (diff < bestDiff) {
                bestDiff = diff;
                bestL = l;
                bestT = t;
            }
        }
        if (sum > 1e-4) {
            L /= sum;
            T /= sum;
        } else {
            L = bestL; // no neighbour at this depth: take the closest in depth
            T = bestT;
        }
    }
    return !(T.r >= 0.99999 && max(L.r, max(L.g, L.b)) <= 0.0);
}

// Window depth of the fog's representative depth: it stands there, so techniques that
// depth-test or sort transparent contributions (stochastic, reference) place it among the
// surfaces.
float fogWindowDepth(float viewDepth) {
    vec4 clip = projection * vec4(0.0, 0.0, -max(viewDepth, 1e-4), 1.0);
    return clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
}
