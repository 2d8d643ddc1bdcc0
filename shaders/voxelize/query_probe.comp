#version 450
// Evaluates the shared slice-map queries (slice_map.glsl) for a list of probes, so tests
// (and debugging tools) can compare them with the C++ twins in src/voxelize/slice_map.cpp.
// Probe i: xyz = world point, w unused; column (probeColumn) for the column queries.
// Output per probe (6 ints): occupied(point), count over [s0, s1], first, last, slice of
// the point (-1 outside), floatBitsToInt(thickness).
#include "slice_map.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = VEIL_SSBO_VOX_AXIS0) readonly buffer Probes { vec4 probes[]; };
layout(std430, binding = VEIL_SSBO_VOX_AXIS0 + 1) readonly buffer ProbeColumns { ivec4 cols[]; };
layout(std430, binding = VEIL_SSBO_VOX_AXIS0 + 2) writeonly buffer Out { int result[]; };
uniform int uProbeCount;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= uProbeCount) return;
    ivec2 c = cols[i].xy;
    ivec2 lc;
    int s;
    bool inside = smLocate(probes[i].xyz, lc, s);
    result[6 * i + 0] = smOccupied(probes[i].xyz) ? 1 : 0;
    result[6 * i + 1] = smCountOccupied(c, cols[i].z, cols[i].w);
    result[6 * i + 2] = smFirstOccupied(c);
    result[6 * i + 3] = smLastOccupied(c);
    result[6 * i + 4] = inside ? s : -1;
    result[6 * i + 5] = floatBitsToInt(smThickness(c));
}
