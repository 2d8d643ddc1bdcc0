#version 450 core
// Transparent casters into the `reference` technique's per-texel lists (lists.glsl), every
// fragment of every view, no depth test (the opaque casters are the depth map's).
#include "../../frame/material.glsl"
#include "../common/views.glsl"
#include "lists.glsl"

layout(binding = 1, r32ui) uniform coherent uimage2DArray shadowHeads;
uniform int shadowView;

void main() {
    float alpha = surfaceCoverage();
    if (alpha <= 0.0) discard;
    vec3 T = clamp(surfaceTransmittance(alpha), vec3(0.0), vec3(1.0));
    if (all(greaterThanEqual(T, vec3(1.0)))) discard;
    uint index = atomicAdd(shadowNodeCount, 1u);
    if (index >= shadowNodeCapacity) discard; // counted: the frame grows the pool and redoes it
    float z = clamp(shadowViewDepth(shadowView, vWorldPos), 0.0, 1.0);
    shadowNodes[index].transmittanceDepth = vec4(T, z);
    shadowNodes[index].next =
        imageAtomicExchange(shadowHeads, ivec3(ivec2(gl_FragCoord.xy), shadowView), index);
}
