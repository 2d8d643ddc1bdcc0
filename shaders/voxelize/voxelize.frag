#version 450
// Slice-map voxelization fragment stage ([Eisemann06 sec. 2]; solid: XOR of crossings).
// Defines:
//   CONSERVATIVE  inputs from conservative.geom: test the pixel square against the triangle
//                 and set every slice of its depth range over the square (else: the one slice
//                 of gl_FragCoord.z at the pixel centre)
//   THREE_AXIS    (with CONSERVATIVE) 6-separating thin voxelization of one dominant-axis
//                 view [Schwarz10 sec. 3.2]: the pixel is kept if the triangle
//                 overlaps the pixel's inscribed diamond, and gets the one slice holding the
//                 triangle's plane at the pixel centre
//   SOLID         set all slices from the crossing to the far end; XOR logic op accumulates
//                 parity, so the inside of a closed mesh ends up set
//   DEPTH_PASS    local slicing's range pass [Eisemann06 sec. 2.2]: output (min, -max) of the slice
//                 coordinate into one RG32F target with GL_MIN blending (near and far in one
//                 pass instead of [Eisemann06]'s two)
//   LOCAL         slices subdivide the column's [near, far] from the range pass
#include "../common/bindings.h"
#include "bits.glsl"

uniform ivec3 uGridSize; // columns x, y; slices
uniform vec2 uViewport;
uniform int uPerspective;
uniform vec2 uNearFar;
uniform int uPass;

#ifdef CONSERVATIVE
flat in vec3 gA;
flat in vec3 gB;
flat in vec3 gC;
#endif
#ifdef LOCAL
layout(binding = VEIL_TEX_VOX_RANGE) uniform sampler2D uRange;
#endif

#ifdef DEPTH_PASS
layout(location = 0) out vec2 oRange;
#else
layout(location = 0) out uvec4 oWords[8];
#endif

float sliceCoord(float windowDepth) {
    if (uPerspective == 0) return windowDepth;
    float n = uNearFar.x, f = uNearFar.y, z = 2.0 * windowDepth - 1.0;
    return (2.0 * n * f / (f + n - z * (f - n)) - n) / (f - n);
}

#ifdef CONSERVATIVE
// Does the interval of the triangle's vertices on axis `n` miss the pixel square?
bool separates(vec2 n, vec2 centre, vec2 half_) {
    float a = dot(n, gA.xy), b = dot(n, gB.xy), c = dot(n, gC.xy);
#ifdef THREE_AXIS
    float p = dot(n, centre), r = max(abs(n.x) * half_.x, abs(n.y) * half_.y); // diamond
#else
    float p = dot(n, centre), r = abs(n.x) * half_.x + abs(n.y) * half_.y; // square
#endif
    float slack = 1e-5 * (abs(n.x) + abs(n.y));
    return min(a, min(b, c)) > p + r + slack || max(a, max(b, c)) < p - r - slack;
}
#endif

void main() {
    vec2 tRange; // slice coordinate range this fragment covers
#ifdef CONSERVATIVE
    vec2 centre = gl_FragCoord.xy / uViewport * 2.0 - 1.0, half_ = 1.0 / uViewport;
    vec2 lo = min(gA.xy, min(gB.xy, gC.xy)), hi = max(gA.xy, max(gB.xy, gC.xy));
    if (any(greaterThan(lo, centre + half_ + 1e-6)) || any(lessThan(hi, centre - half_ - 1e-6)))
        discard;
    vec2 e0 = gB.xy - gA.xy, e1 = gC.xy - gB.xy, e2 = gA.xy - gC.xy;
    if (separates(vec2(-e0.y, e0.x), centre, half_) ||
        separates(vec2(-e1.y, e1.x), centre, half_) || separates(vec2(-e2.y, e2.x), centre, half_))
        discard;
#ifdef THREE_AXIS
    // The diamond's own edge normals.
    if (separates(vec2(half_.y, half_.x), centre, half_) ||
        separates(vec2(half_.y, -half_.x), centre, half_))
        discard;
    vec3 nt = cross(gB - gA, gC - gA); // dominant axis: nt.z is the largest component
    float zc = gA.z - (nt.x * (centre.x - gA.x) + nt.y * (centre.y - gA.y)) / nt.z;
    tRange = vec2(sliceCoord(0.5 * zc + 0.5));
#else
    // Depth range over the square: the triangle's plane, clamped to its vertex depths (a
    // steep triangle spans many slices in one column; [Eisemann06]'s plain raster would leave holes).
    float zlo = min(gA.z, min(gB.z, gC.z)), zhi = max(gA.z, max(gB.z, gC.z));
    vec3 n = cross(gB - gA, gC - gA);
    if (abs(n.z) > 1e-6 * length(n)) {
        float zc = gA.z - (n.x * (centre.x - gA.x) + n.y * (centre.y - gA.y)) / n.z;
        float dz = (abs(n.x) * half_.x + abs(n.y) * half_.y) / abs(n.z);
        zlo = max(zlo, zc - dz);
        zhi = min(zhi, zc + dz);
    }
    tRange = vec2(sliceCoord(0.5 * zlo + 0.5), sliceCoord(0.5 * zhi + 0.5));
#endif
#else
    tRange = vec2(sliceCoord(gl_FragCoord.z));
#endif

#ifdef DEPTH_PASS
    oRange = vec2(tRange.x, -tRange.y);
#else
    vec2 r = vec2(0.0, 1.0);
#ifdef LOCAL
    r = texelFetch(uRange, ivec2(gl_FragCoord.xy), 0).xy * vec2(1.0, -1.0);
    r.y = max(r.y, r.x + 1e-7);
#endif
    vec2 f = (tRange - r.x) / (r.y - r.x) * float(uGridSize.z);
    int k0, k1;
#if defined(SOLID)
    // [Eisemann06] / solid voxelization: toggle every slice whose centre lies beyond the crossing.
    k0 = int(floor(f.x - 0.5)) + 1;
    k1 = uGridSize.z - 1;
#elif defined(CONSERVATIVE) && !defined(THREE_AXIS)
    if (f.y < -1e-3 || f.x > float(uGridSize.z) + 1e-3) discard;
    k0 = clamp(int(floor(f.x - 1e-3)), 0, uGridSize.z - 1);
    k1 = clamp(int(floor(f.y + 1e-3)), 0, uGridSize.z - 1);
#else
    k0 = k1 = clamp(int(floor(f.x)), 0, uGridSize.z - 1);
#endif
    writeRange(uPass, k0, k1, oWords);
#endif
}
