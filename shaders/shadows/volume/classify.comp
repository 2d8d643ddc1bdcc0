#version 450 core
// [Eisemann06 sec. 3.2] per caster and light, from the caster's world bounds projected into the light's
// grid (its footprint, widened by one column):
//   caster culling  : every column of the footprint has an opaque occluder nearer than the
//                     caster's nearest depth -> the caster is in the shadow of others, and so is
//                     its whole shadow volume: not drawn.
//   receiver culling: no camera-visible receiver in the footprint at or behind the caster's
//                     nearest slice -> its volume reaches no receiver: not drawn.
//   clamping        : the volume ends past the farthest such receiver slice (and the caster's
//                     own far depth), instead of at infinity.
// casterClamp[caster * slots + slot]: < 0 culled, 0 infinite, > 0 clamp depth (normalized).
//
// Two dispatches. Reduce (finish false): groups (caster x slot, chunk); group (i, j) takes the
// columns [j, j + 1) * kChunk of i's footprint (64 invocations x kPerInvocation columns,
// contiguous in row order), reduces them in shared memory and then, once per group, into
// footprints[i] with global atomics: a floor's footprint (the whole grid) is spread over
// grid^2 / kChunk groups instead of being looped over by one. Both reductions are maxima, so
// the result does not depend on how the columns are split. Finish (finish true): one
// invocation per (caster, slot) turns footprints[i] into casterClamp[i].
#include "grid.glsl"

const int kPerInvocation = 16;
const int kChunk = 64 * kPerInvocation; // columns per group (kClassifyChunk, classify.h)

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
// Per (caster, slot), cleared to 0 before the reduce: x = the farthest occluder depth's bits
// (non-negative float bits order as uints), y = the farthest receiver slice at or behind the
// caster's nearest slice + 1 (0: none).
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_FOOTPRINTS) coherent buffer Footprints {
    uvec2 footprints[];
};
uniform int casterCount;
uniform int slotCount;
uniform bvec3 uEnable; // caster culling, receiver culling, clamping
uniform bool finish;

// The footprint of caster i in its slot's grid and what is decided without reading it.
struct Footprint {
    bool decided; // by the bounds alone: result is final
    float result;
    ivec2 c0, span;
    int columns;    // 0 when decided
    bool receivers; // the receiver map is read (receiver culling or clamping, bounded light)
    int s0;         // the caster's nearest slice
    float dLo, dHi; // the caster's depth range
};

Footprint footprintOf(int i) {
    Footprint f;
    int caster = i / slotCount, slot = i % slotCount;
    int v = uSlotView[slot];
    f.result = 0.0;
    f.decided = v < 0;
    vec3 lo = casterBounds[2 * caster].xyz, hi = casterBounds[2 * caster + 1].xyz;
    vec2 uvLo = vec2(1e30), uvHi = vec2(-1e30);
    f.dLo = 1e30;
    f.dHi = -1e30;
    for (int k = 0; k < 8 && !f.decided; ++k) {
        vec3 P = mix(lo, hi, vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
        vec4 c = shadows.views[v].worldToTexture * vec4(P, 1.0);
        if (c.w <= 1e-6) f.decided = true; // reaches behind the light: drawn, unclamped
        uvLo = min(uvLo, c.xy / c.w);
        uvHi = max(uvHi, c.xy / c.w);
        float d = shadowViewDepth(v, P);
        f.dLo = min(f.dLo, d);
        f.dHi = max(f.dHi, d);
    }
    f.c0 = ivec2(floor(uvLo * float(uGrid))) - 1;
    ivec2 c1 = ivec2(floor(uvHi * float(uGrid))) + 1;
    if (!f.decided && (any(lessThan(c1, ivec2(0))) || any(greaterThanEqual(f.c0, ivec2(uGrid))))) {
        // Outside the light's view: the light reaches no receiver behind it.
        if (uEnable.y && unbounded[slot] == 0u) f.result = -1.0;
        f.decided = true;
    }
    f.c0 = max(f.c0, ivec2(0));
    c1 = min(c1, ivec2(uGrid - 1));
    f.span = c1 - f.c0 + 1;
    f.columns = f.decided ? 0 : f.span.x * f.span.y;
    f.receivers = !f.decided && unbounded[slot] == 0u && (uEnable.y || uEnable.z);
    f.s0 = clamp(int(floor(f.dLo * float(uSlices))), 0, uSlices - 1);
    return f;
}

shared uint sFarBits;
shared int sLast;

void reduce() {
    int i = int(gl_WorkGroupID.x);
    uint t = gl_LocalInvocationIndex;
    if (i >= casterCount * slotCount) return;
    // Uniform over the group: all of it leaves here or none.
    Footprint f = footprintOf(i);
    int first = int(gl_WorkGroupID.y) * kChunk;
    if (first >= f.columns) return;
    if (t == 0u) {
        sFarBits = 0u;
        sLast = -1;
    }
    barrier();
    int slot = i % slotCount, words = gridWords(), end = min(first + kChunk, f.columns);
    uint farBits = 0u;
    int last = -1;
    for (int n = first + int(t); n < end; n += 64) {
        ivec2 col = f.c0 + ivec2(n % f.span.x, n / f.span.x);
        int g = gridColumn(slot, col);
        if (uEnable.x) farBits = max(farBits, floatBitsToUint(max(occluderFar[g], 0.0)));
        if (!f.receivers) continue;
        for (int w = words - 1; w >= f.s0 / 32 && w * 32 + 31 > last; --w) {
            uint bits = receiverWords[g * words + w];
            if (w == f.s0 / 32) bits &= ~0u << uint(f.s0 % 32);
            if (bits != 0u) {
                last = max(last, w * 32 + findMSB(bits));
                break;
            }
        }
    }
    if (farBits != 0u) atomicMax(sFarBits, farBits);
    if (last >= 0) atomicMax(sLast, last);
    barrier();
    if (t != 0u) return;
    if (sFarBits != 0u) atomicMax(footprints[i].x, sFarBits);
    if (sLast >= 0) atomicMax(footprints[i].y, uint(sLast + 1));
}

void main() {
    if (!finish) {
        reduce();
        return;
    }
    int i = int(gl_GlobalInvocationID.x);
    if (i >= casterCount * slotCount) return;
    Footprint f = footprintOf(i);
    float result = f.result;
    if (!f.decided) {
        uvec2 r = footprints[i];
        if (uEnable.x && uintBitsToFloat(r.x) < f.dLo) {
            result = -1.0; // in the shadow of other casters
        } else if (f.receivers) {
            int last = int(r.y) - 1;
            if (last < 0) {
                if (uEnable.y) result = -1.0;
            } else if (uEnable.z) {
                // Past the receivers' slice with one slice of margin (the receivers were placed
                // from the depth buffer), and never before the caster's own far side (the
                // extrusion must not fold).
                result = max(f.dHi, float(last + 2) / float(uSlices)) + 1e-4;
            }
        }
    }
    casterClamp[i] = result;
}
