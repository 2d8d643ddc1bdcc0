// Slice-map queries shared by every module that reads a voxelization (the C++ twin is
// src/voxelize/slice_map.{h,cpp}; layouts documented there). [Eisemann06 sec. 2]: a column of the
// grid camera's image holds one bit per slice, 32 slices per word.
//
// Expects the SSBOs below bound and these uniforms set (SliceMapGpu::bind does both):
//   uSmSize (ivec3: width, height, slices), uSmViewProj, uSmPerspective, uSmNearFar
//   (perspective eye near/far), uSmLocal (1 = per-column ranges in the range buffer).
#ifndef VEIL_VOXELIZE_SLICE_MAP_GLSL
#define VEIL_VOXELIZE_SLICE_MAP_GLSL

#include "../common/bindings.h"

layout(std430, binding = VEIL_SSBO_VOX_WORDS) readonly buffer SliceMapWords { uint smWords[]; };
layout(std430, binding = VEIL_SSBO_VOX_RANGE) readonly buffer SliceMapRange { vec2 smRange[]; };

uniform ivec3 uSmSize;
uniform mat4 uSmViewProj;
uniform int uSmPerspective;
uniform vec2 uSmNearFar;
uniform int uSmLocal;

int smWordsPerColumn() { return (uSmSize.z + 31) / 32; }
int smColumn(ivec2 c) { return c.y * uSmSize.x + c.x; }

float smDepthToSliceCoord(float d) {
    if (uSmPerspective == 0) return d;
    float n = uSmNearFar.x, f = uSmNearFar.y, z = 2.0 * d - 1.0;
    float eye = 2.0 * n * f / (f + n - z * (f - n));
    return (eye - n) / (f - n);
}

vec2 smColumnRange(ivec2 c) {
    if (uSmLocal == 0) return vec2(0.0, 1.0);
    vec2 r = smRange[smColumn(c)];
    return vec2(r.x, max(r.y, r.x + 1e-7));
}

bool smGet(ivec2 c, int s) {
    uint w = smWords[smColumn(c) * smWordsPerColumn() + s / 32];
    return ((w >> uint(s % 32)) & 1u) != 0u;
}

// Column and slice of a world point; false outside the grid.
bool smLocate(vec3 world, out ivec2 c, out int s) {
    vec4 clip = uSmViewProj * vec4(world, 1.0);
    c = ivec2(0);
    s = 0;
    if (clip.w <= 0.0) return false;
    vec3 ndc = clip.xyz / clip.w;
    vec2 f = (ndc.xy * 0.5 + 0.5) * vec2(uSmSize.xy);
    if (any(lessThan(f, vec2(0.0))) || any(greaterThanEqual(f, vec2(uSmSize.xy)))) return false;
    c = ivec2(f);
    vec2 r = smColumnRange(c);
    if (uSmLocal != 0 && smRange[smColumn(c)].x > smRange[smColumn(c)].y) return false;
    float fs = (smDepthToSliceCoord(ndc.z * 0.5 + 0.5) - r.x) / (r.y - r.x) * float(uSmSize.z);
    // Local ranges are closed (near and far belong to the first and last slice).
    float slack = uSmLocal != 0 ? 1e-3 : 0.0;
    if (fs < -slack || fs >= float(uSmSize.z) + slack) return false;
    s = clamp(int(floor(fs)), 0, uSmSize.z - 1);
    return true;
}

bool smOccupied(vec3 world) {
    ivec2 c;
    int s;
    return smLocate(world, c, s) && smGet(c, s);
}

// Set slices in [s0, s1] of a column: popcount over the words the range touches.
int smCountOccupied(ivec2 c, int s0, int s1) {
    s0 = max(s0, 0);
    s1 = min(s1, uSmSize.z - 1);
    int n = 0, base = smColumn(c) * smWordsPerColumn();
    for (int w = s0 / 32; w <= s1 / 32 && s0 <= s1; ++w) {
        uint m = 0xffffffffu;
        if (w == s0 / 32) m &= 0xffffffffu << uint(s0 % 32);
        if (w == s1 / 32 && s1 % 32 != 31) m &= (1u << uint(s1 % 32 + 1)) - 1u;
        n += bitCount(smWords[base + w] & m);
    }
    return n;
}

int smFirstOccupied(ivec2 c) {
    int base = smColumn(c) * smWordsPerColumn();
    for (int w = 0; w < smWordsPerColumn(); ++w)
        if (smWords[base + w] != 0u) return w * 32 + findLSB(smWords[base + w]);
    return -1;
}

int smLastOccupied(ivec2 c) {
    int base = smColumn(c) * smWordsPerColumn();
    for (int w = smWordsPerColumn() - 1; w >= 0; --w)
        if (smWords[base + w] != 0u) return w * 32 + findMSB(smWords[base + w]);
    return -1;
}

// World length of a column's set slices: count times the slice length along the column's
// centre ray (slices are equal steps of the slice coordinate, linear along that ray).
vec3 smCellCenter(ivec2 c, float slice) {
    vec2 r = smColumnRange(c);
    float t = r.x + slice / float(uSmSize.z) * (r.y - r.x);
    float d = t;
    if (uSmPerspective != 0) {
        float n = uSmNearFar.x, f = uSmNearFar.y, eye = n + t * (f - n);
        d = 0.5 * ((f + n) / (f - n) - 2.0 * f * n / ((f - n) * eye)) + 0.5;
    }
    vec4 ndc = vec4((vec2(c) + 0.5) / vec2(uSmSize.xy) * 2.0 - 1.0, 2.0 * d - 1.0, 1.0);
    vec4 w = inverse(uSmViewProj) * ndc;
    return w.xyz / w.w;
}

float smThickness(ivec2 c) {
    float step = length(smCellCenter(c, 1.5) - smCellCenter(c, 0.5));
    return step * float(smCountOccupied(c, 0, uSmSize.z - 1));
}

#endif
