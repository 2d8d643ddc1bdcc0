// OIT technique `reference`: exact per-pixel sorted compositing. oitEmit appends one node to
// the pixel's linked list (head pointer in an r32ui image, nodes in an SSBO pool, an atomic
// node counter); shaders/oit/reference/resolve.comp sorts each list by depth and composites
// front to back. Each node stores
//   radiance   = alpha * L_r (premultiplied), depth = view depth,
//   modulation = 1 - alpha + alpha * T (000 Eq. 2, per channel).
// The counter keeps counting past the pool's capacity; the host reads it back and, when it
// exceeds the pool, grows the pool and re-renders (reference.h).
//
// Fog marcher: a compute shader calls this same oitEmit() once per segment between surfaces:
// it #defines OIT_PIXEL_COORD (its ivec2 pixel) and OIT_FOG_SEGMENTS before including this
// file, reads the pixel's surface depths with oitSurfaceDepths() and emits one node per
// segment, which then takes part in the sort like any surface fragment.
#include "../fragment.glsl"

#include "../../common/bindings.h"

#ifndef OIT_PIXEL_COORD
#define OIT_PIXEL_COORD ivec2(gl_FragCoord.xy)
// Appending is a side effect: it must only happen for fragments that pass the depth test
// against the opaque depth, so the test runs before the shader.
layout(early_fragment_tests) in;
#endif

struct OitRefNode {
    vec3 radiance;
    float depth;
    vec3 modulation;
    uint next;
};
#ifdef OIT_FOG_SEGMENTS
layout(std430, binding = VEIL_SSBO_OIT_REF_NODES) restrict buffer OitRefNodes {
#else
layout(std430, binding = VEIL_SSBO_OIT_REF_NODES) restrict writeonly buffer OitRefNodes {
#endif
    OitRefNode oitRefNodes[];
};
layout(std430, binding = VEIL_SSBO_OIT_REF_COUNTERS) restrict buffer OitRefCounters {
    uint oitRefRequested; // nodes requested this accumulation (may exceed the capacity)
    uint oitRefDropped;   // written by the resolve
};
layout(binding = VEIL_IMG_OIT_REF_HEADS, r32ui) uniform restrict uimage2D oitRefHeads;
uniform uint oitRefCapacity;

void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    uint node = atomicAdd(oitRefRequested, 1u);
    if (node >= oitRefCapacity) return; // counted; the host grows the pool and re-renders
    uint next = imageAtomicExchange(oitRefHeads, OIT_PIXEL_COORD, node);
    oitRefNodes[node].radiance = radiance;
    oitRefNodes[node].depth = viewDepth;
    oitRefNodes[node].modulation = vec3(1.0 - alpha) + alpha * transmission;
    oitRefNodes[node].next = next;
}

#ifdef OIT_FOG_SEGMENTS
#ifndef OIT_REF_MAX_FRAGMENTS
#error "OIT_REF_MAX_FRAGMENTS must be defined (the technique's defines())"
#endif
#define OIT_SURFACE_DEPTHS_MAX OIT_REF_MAX_FRAGMENTS
// View depths of the nodes in pixel p's list, nearest first (insertion sort while walking;
// past OIT_REF_MAX_FRAGMENTS the nearest are kept, as in the resolve). Returns their count.
int oitSurfaceDepths(ivec2 p, out float depths[OIT_SURFACE_DEPTHS_MAX]) {
    int count = 0;
    uint index = imageLoad(oitRefHeads, p).r;
    for (uint guard = 0u; index < oitRefCapacity && guard < oitRefCapacity; ++guard) {
        float d = oitRefNodes[index].depth;
        index = oitRefNodes[index].next;
        int j = count;
        if (count == OIT_SURFACE_DEPTHS_MAX) {
            if (d >= depths[count - 1]) continue;
            j = count - 1;
        } else {
            ++count;
        }
        while (j > 0 && depths[j - 1] > d) {
            depths[j] = depths[j - 1];
            --j;
        }
        depths[j] = d;
    }
    return count;
}
#endif
