// "veil:light_visibility" of the `reference` shadow technique (src/shadows/reference/
// reference.h): exact light visibility at the maps' texel resolution, for tests and
// comparisons. Opaque casters: the depth map (PCF radius as set; 0 = a hard test); transparent
// casters: the product of the transmittances of every fragment of the receiver's texel in
// front of it; density volumes: their optical depth marched from the receiver to the light
// (or out of the volumes' bounds for a directional light) in `media_steps` midpoint steps.
//
// params[1]: x = receiver depth offset (world units toward the light), y = media steps,
// z = list traversal limit.
#include "../common/opaque_depth.glsl"
#include "../../volume/volume_common.glsl"
#include "lists.glsl"

layout(binding = VEIL_TEX_SHADOW1) uniform usampler2DArray shadowHeadMap;

vec3 referenceListTransmittance(int v, vec2 uv, float depth) {
    ivec2 size = ivec2(shadows.mapSize.x);
    ivec2 texel = clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);
    uint node = texelFetch(shadowHeadMap, ivec3(texel, v), 0).r;
    vec3 T = vec3(1.0);
    int limit = int(shadows.params[1].z);
    for (int k = 0; k < limit && node != kShadowListEnd; ++k) {
        vec4 n = shadowNodes[node].transmittanceDepth;
        if (n.a < depth) T *= n.rgb;
        node = shadowNodes[node].next;
    }
    return T;
}

// Transmittance through the density volumes from P toward light i.
vec3 referenceMediaTransmittance(int i, vec3 P) {
    if (volumeCount == 0) return vec3(1.0);
    vec3 L;
    float tMax;
    if (int(lighting.lights[i].positionType.w) == VEIL_LIGHT_DIRECTIONAL) {
        L = -lighting.lights[i].directionShadow.xyz;
        tMax = 1e30;
    } else {
        vec3 d = lighting.lights[i].positionType.xyz - P;
        tMax = length(d);
        L = d / max(tMax, 1e-20);
    }
    float t0 = 1e30, t1 = -1e30;
    for (int k = 0; k < volumeCount; ++k) {
        vec2 iv = volumeBoxInterval(k, P, L);
        if (iv.x < iv.y) {
            t0 = min(t0, iv.x);
            t1 = max(t1, iv.y);
        }
    }
    t0 = max(t0, 0.0);
    t1 = min(t1, tMax);
    if (!(t0 < t1)) return vec3(1.0);
    int steps = int(shadows.params[1].y);
    float dt = (t1 - t0) / float(steps);
    // The same midpoint sum, kReferenceUnroll samples per loop iteration: Mesa's llvmpipe ends
    // an invocation's loops after 65535 iterations in all (reference.cpp), and the fog marcher
    // calls this once per step of its own loop, so the unrolled body keeps fog_steps x
    // (media_steps / kReferenceUnroll + kReferenceUnroll) within that budget at the defaults.
    const int kReferenceUnroll = 8;
    float tau = 0.0;
    int s = 0;
    for (; s + kReferenceUnroll <= steps; s += kReferenceUnroll) {
        vec3 Q = P + L * (t0 + (float(s) + 0.5) * dt), D = L * dt;
        tau += volumeExtinction(Q) + volumeExtinction(Q + D) + volumeExtinction(Q + 2.0 * D) +
               volumeExtinction(Q + 3.0 * D) + volumeExtinction(Q + 4.0 * D) +
               volumeExtinction(Q + 5.0 * D) + volumeExtinction(Q + 6.0 * D) +
               volumeExtinction(Q + 7.0 * D);
    }
    for (; s < steps; ++s) tau += volumeExtinction(P + L * (t0 + (float(s) + 0.5) * dt));
    return vec3(exp(-tau * dt));
}

vec3 referenceVisibility(int i, vec3 P, float opaque) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(i, P, v, uv, z)) return vec3(opaque) * referenceMediaTransmittance(i, P);
    float offset = shadows.params[1].x / shadowViewDepthScale(v);
    return opaque * referenceListTransmittance(v, uv, z - offset) *
           referenceMediaTransmittance(i, P);
}

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
    radiance *= referenceVisibility(i, P, opaqueVisibility(i, P, N, L));
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
    radiance *= referenceVisibility(i, P, opaqueVisibilityFast(i, P));
}

#include "../common/visibility_values.glsl"
