#version 450 core
// OIT `reference` resolve: per pixel, gather the linked list into a local array of the
// OIT_REF_MAX_FRAGMENTS nearest fragments (insertion sort by view depth while gathering),
// then composite front to back over the opaque image ([Enderton11 Eq. 2] with colored modulation):
//     C = sum_i (prod_{j<i} m_j) c_i + (prod_j m_j) * background.
// Fragments beyond the nearest OIT_REF_MAX_FRAGMENTS are counted in oitRefDropped, and the
// deepest list of the frame in oitRefMaxLength (what max_fragments_per_pixel must reach).
// Every pixel's list length (its nodes: surface fragments and, with fog, one per fog
// segment) goes to oitRefCount, the frame resource oit.reference.fragments_per_pixel.
#include "../../common/bindings.h"
#include "../../common/region.glsl"

#ifndef OIT_REF_MAX_FRAGMENTS
#error "OIT_REF_MAX_FRAGMENTS must be defined (size of the per-pixel sort array)"
#endif

layout(local_size_x = 8, local_size_y = 8) in;

struct OitRefNode {
    vec3 radiance;
    float depth;
    vec3 modulation;
    uint next;
};
layout(std430, binding = VEIL_SSBO_OIT_REF_NODES) restrict readonly buffer OitRefNodes {
    OitRefNode oitRefNodes[];
};
layout(std430, binding = VEIL_SSBO_OIT_REF_COUNTERS) restrict buffer OitRefCounters {
    uint oitRefRequested;
    uint oitRefDropped;
    uint oitRefMaxLength;
};
layout(binding = VEIL_IMG_OIT_REF_HEADS, r32ui) uniform restrict readonly uimage2D oitRefHeads;
layout(binding = VEIL_IMG_OIT_REF_TARGET, rgba16f) uniform restrict image2D hdrImage;
layout(binding = VEIL_IMG_OIT_REF_COUNT, r32f) uniform restrict writeonly image2D oitRefCount;
uniform uint oitRefCapacity;

const uint kEnd = 0xFFFFFFFFu;

void main() {
    ivec2 size = imageSize(hdrImage);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    uint index = imageLoad(oitRefHeads, p).r;
    if (index == kEnd) {
        imageStore(oitRefCount, p, vec4(0.0));
        return;
    }

    float depths[OIT_REF_MAX_FRAGMENTS];
    uint ids[OIT_REF_MAX_FRAGMENTS];
    int count = 0;
    uint dropped = 0u;
    // The guard bounds the walk even if a list were corrupt.
    for (uint guard = 0u; index < oitRefCapacity && guard < oitRefCapacity; ++guard) {
        float d = oitRefNodes[index].depth;
        int j = count;
        if (count == OIT_REF_MAX_FRAGMENTS) {
            ++dropped; // either this fragment or the current farthest one goes
            if (d >= depths[count - 1]) {
                index = oitRefNodes[index].next;
                continue;
            }
            j = count - 1;
        } else {
            ++count;
        }
        while (j > 0 && depths[j - 1] > d) {
            depths[j] = depths[j - 1];
            ids[j] = ids[j - 1];
            --j;
        }
        depths[j] = d;
        ids[j] = index;
        index = oitRefNodes[index].next;
    }
    if (dropped > 0u) atomicAdd(oitRefDropped, dropped);
    atomicMax(oitRefMaxLength, uint(count) + dropped);
    imageStore(oitRefCount, p, vec4(float(uint(count) + dropped)));

    vec3 color = vec3(0.0), throughput = vec3(1.0);
    for (int i = 0; i < count; ++i) {
        color += throughput * oitRefNodes[ids[i]].radiance;
        throughput *= oitRefNodes[ids[i]].modulation;
    }
    vec4 background = imageLoad(hdrImage, p);
    imageStore(hdrImage, p, vec4(color + throughput * background.rgb, background.a));
}
