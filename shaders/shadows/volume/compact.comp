#version 450 core
// Shadow volumes (src/shadows/volume), per light: the casters that classify.comp did not cull
// [Eisemann06 sec. 3.2] into a compact work list with the prefix sum of their triangles, and the
// indirect dispatch of silhouette.comp over exactly those triangles: a culled caster's
// triangles are never launched. One workgroup; each invocation owns a run of casters.
// With `finish` (after silhouette.comp): the first point of the depth-pass draw.
#include "draw.glsl"

layout(local_size_x = 256) in;
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_CASTERS) readonly buffer Casters {
    float casterClamp[]; // < 0 culled
};
uniform int casterCount;
uniform int slot;
uniform int slotCount;
uniform bool finish;
uniform uint capacity; // points in triangles[]

shared uint sCasters[256], sTriangles[256];

bool survives(int c) { return casterClamp[c * slotCount + slot] >= 0.0 && ranges[c].triangles > 0u; }

void main() {
    uint t = gl_LocalInvocationIndex;
    if (finish) {
        if (t == 0u) passFirst = capacity - passCount;
        return;
    }
    int per = (casterCount + 255) / 256;
    int c0 = min(int(t) * per, casterCount), c1 = min(c0 + per, casterCount);
    uint n = 0u, tris = 0u;
    for (int c = c0; c < c1; ++c)
        if (survives(c)) {
            ++n;
            tris += ranges[c].triangles;
        }
    sCasters[t] = n;
    sTriangles[t] = tris;
    barrier();
    for (uint d = 1u; d < 256u; d *= 2u) { // inclusive scan (Hillis-Steele)
        uint a = t >= d ? sCasters[t - d] : 0u, b = t >= d ? sTriangles[t - d] : 0u;
        barrier();
        sCasters[t] += a;
        sTriangles[t] += b;
        barrier();
    }
    uint k = sCasters[t] - n, first = sTriangles[t] - tris;
    for (int c = c0; c < c1; ++c)
        if (survives(c)) {
            work[k++] = uvec2(uint(c), first);
            first += ranges[c].triangles;
        }
    if (t == 255u) {
        drawCount = 0u;
        drawInstances = 1u;
        drawFirst = 0u;
        drawBase = 0u;
        submitted = sTriangles[255];
        survivors = sCasters[255];
        groupsX = (submitted + 63u) / 64u;
        groupsY = 1u;
        groupsZ = 1u;
        silhouetteEdges = 0u;
        fanTriangles = 0u;
        passTriangles = 0u;
        passCount = 0u;
        passInstances = 1u;
        passFirst = capacity;
        passBase = 0u;
    }
}
