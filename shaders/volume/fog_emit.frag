#version 450 core
// Hands the marched fog of this pixel to the active OIT technique as one contribution (001
// section 7.2: "a single full-screen quad that models ray-marched OIT fog"): radiance L with
// coverage 1 and transmission T, at the fog's representative depth. Reduced-resolution fog is
// upsampled with a joint bilateral filter keyed on the opaque depth (000 section 5).
#include "../common/camera.glsl"

#include "veil:oit_emit"

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

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 L, T;
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
    if (T.r >= 0.99999 && max(L.r, max(L.g, L.b)) <= 0.0) discard;
    // Stand at the fog's representative depth, so techniques that depth-test or sort
    // transparent fragments (stochastic, reference) place it among the surfaces.
    vec4 clip = projection * vec4(0.0, 0.0, -max(L.a, 1e-4), 1.0);
    gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
    oitEmit(oitFragment(L.rgb, 1.0, T.rgb, L.a)); // no surface, no particle
}
