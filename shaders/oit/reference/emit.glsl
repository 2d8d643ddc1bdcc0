// OIT technique `reference`: exact per-pixel sorted compositing. oitEmit appends one node to
// the pixel's linked list (head pointer in an r32ui image, nodes in an SSBO pool, an atomic
// node counter); shaders/oit/reference/resolve.comp sorts each list by depth and composites
// front to back. Each node stores
//   radiance   = alpha * L_r (premultiplied), depth = view depth,
//   modulation = 1 - alpha + alpha * T ([McGuire16 Eq. 2], per channel).
// The counter keeps counting past the pool's capacity; the host reads it back and, when it
// exceeds the pool, grows the pool and re-renders (reference.h).
//
// Fog marcher: a compute shader calls this same oitEmit() once per segment between surfaces:
// it #defines OIT_PIXEL_COORD (its ivec2 pixel) and OIT_FOG_SEGMENTS before including this
// file, walks the pixel's surfaces with oitNextSurfaceDepth() and emits one node per
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
// The surfaces stored so far at pixel p, as a handle for oitNextSurfaceDepth(): the head of its
// list, taken before the fog appends its own nodes (which go in front of it, unseen by walks
// from this handle).
uint oitSurfaceList(ivec2 p) { return imageLoad(oitRefHeads, p).r; }

// The nearest view depth greater than `after` among the surfaces of `list` (1e30: none).
// Surfaces of equal depth are returned once (the segment between them is empty). A walk of the
// list per surface: no local array (a 128-entry one made the marcher 5x slower on the H200),
// quadratic only in the depth of pixels that have fog.
float oitNextSurfaceDepth(uint list, float after) {
    float next = 1e30;
    for (uint guard = 0u; list < oitRefCapacity && guard < oitRefCapacity; ++guard) {
        float d = oitRefNodes[list].depth;
        if (d > after) next = min(next, d);
        list = oitRefNodes[list].next;
    }
    return next;
}
#endif
