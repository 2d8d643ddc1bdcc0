#version 450 core
// 003 Sec. 3.2 per caster and light, from the caster's world bounds projected into the light's
// grid (its footprint, widened by one column):
//   caster culling  : every column of the footprint has an opaque occluder nearer than the
//                     caster's nearest depth -> the caster is in the shadow of others, and so is
//                     its whole shadow volume: not drawn.
//   receiver culling: no camera-visible receiver in the footprint at or behind the caster's
//                     nearest slice -> its volume reaches no receiver: not drawn.
//   clamping        : the volume ends past the farthest such receiver slice (and the caster's
//                     own far depth), instead of at infinity.
// casterClamp[caster * slots + slot]: < 0 culled, 0 infinite, > 0 clamp depth (normalized).
#include "grid.glsl"

// One workgroup per caster and light: the footprint's columns are shared among its 64
// invocations (a floor's footprint is the whole grid), reduced with shared atomics.
layout(local_size_x = 64) in;
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_RECEIVERS) readonly buffer Receivers {
    uint unbounded[VEIL_MAX_LIGHTS];
    uint receiverWords[];
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_OCCLUDERS) readonly buffer Occluders {
    float occluderFar[];
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_BOUNDS) readonly buffer Bounds {
    vec4 casterBounds[]; // world lo, hi per caster
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_CASTERS) writeonly buffer Casters {
    float casterClamp[];
};
uniform int casterCount;
uniform int slotCount;
uniform bvec3 uEnable; // caster culling, receiver culling, clamping

shared uint sFarBits; // the farthest occluder depth (non-negative float bits order as uints)
shared int sLast;     // the farthest receiver slice at or behind the caster

void main() {
    int i = int(gl_WorkGroupID.x);
    uint t = gl_LocalInvocationIndex;
    if (i >= casterCount * slotCount) return;
    int caster = i / slotCount, slot = i % slotCount;
    int v = uSlotView[slot];
    if (t == 0u) {
        sFarBits = 0u;
        sLast = -1;
    }
    barrier();
    // Everything up to the column loops is uniform over the workgroup.
    float result = 0.0;
    bool decided = v < 0;
    vec3 lo = casterBounds[2 * caster].xyz, hi = casterBounds[2 * caster + 1].xyz;
    vec2 uvLo = vec2(1e30), uvHi = vec2(-1e30);
    float dLo = 1e30, dHi = -1e30;
    for (int k = 0; k < 8 && !decided; ++k) {
        vec3 P = mix(lo, hi, vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
        vec4 c = shadows.views[v].worldToTexture * vec4(P, 1.0);
        if (c.w <= 1e-6) decided = true; // reaches behind the light: drawn, unclamped
        uvLo = min(uvLo, c.xy / c.w);
        uvHi = max(uvHi, c.xy / c.w);
        float d = shadowViewDepth(v, P);
        dLo = min(dLo, d);
        dHi = max(dHi, d);
    }
    ivec2 c0 = ivec2(floor(uvLo * float(uGrid))) - 1, c1 = ivec2(floor(uvHi * float(uGrid))) + 1;
    if (!decided && (any(lessThan(c1, ivec2(0))) || any(greaterThanEqual(c0, ivec2(uGrid))))) {
        // Outside the light's view: the light reaches no receiver behind it.
        if (uEnable.y && unbounded[slot] == 0u) result = -1.0;
        decided = true;
    }
    c0 = max(c0, ivec2(0));
    c1 = min(c1, ivec2(uGrid - 1));
    ivec2 span = c1 - c0 + 1;
    int columns = decided ? 0 : span.x * span.y;
    bool receivers = !decided && unbounded[slot] == 0u && (uEnable.y || uEnable.z);
    int s0 = clamp(int(floor(dLo * float(uSlices))), 0, uSlices - 1);
    int words = gridWords();
    for (int n = int(t); n < columns; n += 64) {
        ivec2 col = c0 + ivec2(n % span.x, n / span.x);
        int g = gridColumn(slot, col);
        if (uEnable.x) atomicMax(sFarBits, floatBitsToUint(max(occluderFar[g], 0.0)));
        if (!receivers) continue;
        for (int w = words - 1; w >= s0 / 32; --w) {
            uint bits = receiverWords[g * words + w];
            if (w == s0 / 32) bits &= ~0u << uint(s0 % 32);
            if (bits != 0u) {
                atomicMax(sLast, w * 32 + findMSB(bits));
                break;
            }
        }
    }
    barrier();
    if (t != 0u) return;
    if (!decided) {
        if (uEnable.x && uintBitsToFloat(sFarBits) < dLo) {
            result = -1.0; // in the shadow of other casters
        } else if (receivers) {
            int last = sLast;
            if (last < 0) {
                if (uEnable.y) result = -1.0;
            } else if (uEnable.z) {
                // Past the receivers' slice with one slice of margin (the receivers were placed
                // from the depth buffer), and never before the caster's own far side (the
                // extrusion must not fold).
                result = max(dHi, float(last + 2) / float(uSlices)) + 1e-4;
            }
        }
    }
    casterClamp[i] = result;
}
