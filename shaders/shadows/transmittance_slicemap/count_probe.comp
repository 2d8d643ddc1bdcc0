#version 450
// Evaluates slices.glsl's slmAttenuation for a list of probes, so tests can compare the GPU's
// bitCount-over-masked-words attenuation with a CPU double-precision model built on
// src/voxelize's SliceMap::countOccupied (tests/gl/shadow_slicemap_test.cpp).
// Probe i: x = view, y = column, z = s1 (last slice in front of the receiver), w unused.
// Output per probe: the attenuation (vec4, w = 0).
#include "slices.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = VEIL_SSBO_SHADOW_SLICES + 1) readonly buffer Probes { ivec4 probes[]; };
layout(std430, binding = VEIL_SSBO_SHADOW_SLICES + 2) writeonly buffer Out { vec4 result[]; };
uniform int uProbeCount;
uniform int uClasses;
uniform int uColumns;
uniform int uSlices;
uniform vec3 uClassT[3];

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= uProbeCount) return;
    vec3 classT[3] = uClassT;
    result[i] = vec4(slmAttenuation(probes[i].x, uClasses, uColumns, (uSlices + 31) / 32,
                                    probes[i].y, probes[i].z, classT),
                     0.0);
}
