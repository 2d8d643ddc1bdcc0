#version 450
// Compute surface voxelization, one thread per (triangle, tile) ([Schwarz10],
// Sec. 3.1; tiles of 4 x 4 columns x 32 slices = one word, so no thread loops long: llvmpipe
// ends loops after 65535 iterations, and big triangles would starve a warp on GPUs):
// a cell of the triangle's bounding box is set iff the triangle's plane crosses the cell
// (critical-point test) and the triangle's projections onto the xy, yz and zx planes overlap
// the cell's projections (three 2D edge tests each). That is the exact triangle/box overlap
// for closed cells. Works in grid index space (cell = unit cube); the words are OR-ed with
// atomicOr into the slice-map SSBO (layout: src/voxelize/slice_map.h).
#include "../common/bindings.h"
layout(local_size_x = 64) in;
layout(std430, binding = VEIL_SSBO_VOX_WORDS) buffer Words { uint words[]; };
layout(std430, binding = VEIL_SSBO_VOX_TRIS) readonly buffer Tris { float tris[]; };
// Exclusive prefix sum of tiles per triangle (count + 1 entries, CPU-built): work item i
// belongs to the triangle t with tileStart[t] <= i < tileStart[t + 1].
// COUNT_TILES: the pre-pass that writes each triangle's tile count into this buffer (one
// thread per triangle) with the very bounds the voxelizing pass uses.
#ifdef COUNT_TILES
layout(std430, binding = VEIL_SSBO_VOX_TRIS + 1) writeonly buffer TileStart { uint tileStart[]; };
#else
layout(std430, binding = VEIL_SSBO_VOX_TRIS + 1) readonly buffer TileStart { uint tileStart[]; };
#endif
uniform ivec3 uGridSize;
uniform vec3 uGridLo;
uniform vec3 uVoxel;
uniform uint uItemOffset;
uniform uint uItemCount;
uniform uint uTriangleCount;
const ivec3 kTile = ivec3(4, 4, 32);

const float kSlack = 1e-4; // in cell units: float rounding must not drop a touching cell

vec3 vertexAt(uint t, int k) {
    uint i = 9u * t + uint(3 * k);
    return (vec3(tris[i], tris[i + 1u], tris[i + 2u]) - uGridLo) / uVoxel;
}

// Edge functions of one 2D projection [Schwarz10 Eq. 3-4]; `s` orients them by the
// normal's component along the projection axis.
struct Edges2D {
    vec2 n[3];
    float d[3];
};
Edges2D edges2D(vec2 v0, vec2 v1, vec2 v2, float s) {
    Edges2D e;
    vec2 v[3] = vec2[3](v0, v1, v2);
    for (int i = 0; i < 3; ++i) {
        vec2 ed = v[(i + 1) % 3] - v[i];
        e.n[i] = vec2(-ed.y, ed.x) * (s >= 0.0 ? 1.0 : -1.0);
        e.d[i] = -dot(e.n[i], v[i]) + max(0.0, e.n[i].x) + max(0.0, e.n[i].y);
    }
    return e;
}
bool inside2D(Edges2D e, vec2 p) {
    for (int i = 0; i < 3; ++i) {
        float scale = abs(e.n[i].x) + abs(e.n[i].y);
        if (dot(e.n[i], p) + e.d[i] < -kSlack * scale) return false;
    }
    return true;
}

void main() {
    if (gl_GlobalInvocationID.x >= uItemCount) return;
    uint item = gl_GlobalInvocationID.x + uItemOffset;
#ifdef COUNT_TILES
    uint t = item, tile = 0u;
#else
    uint a = 0u, b = uTriangleCount; // binary search: tileStart[a] <= item < tileStart[b]
    while (b - a > 1u) {
        uint m = (a + b) / 2u;
        if (tileStart[m] <= item)
            a = m;
        else
            b = m;
    }
    uint t = a, tile = item - tileStart[t];
#endif
    vec3 v0 = vertexAt(t, 0), v1 = vertexAt(t, 1), v2 = vertexAt(t, 2);
    vec3 n = cross(v1 - v0, v2 - v0);
    // Plane test: the cell [p, p+1] straddles the plane iff the plane separates the
    // critical corner c and its opposite (Eq. 1-2).
    vec3 c = vec3(n.x > 0.0 ? 1.0 : 0.0, n.y > 0.0 ? 1.0 : 0.0, n.z > 0.0 ? 1.0 : 0.0);
    float d1 = dot(n, c - v0), d2 = dot(n, (vec3(1.0) - c) - v0);
    float planeSlack = kSlack * (abs(n.x) + abs(n.y) + abs(n.z));
    Edges2D exy = edges2D(v0.xy, v1.xy, v2.xy, n.z);
    Edges2D eyz = edges2D(v0.yz, v1.yz, v2.yz, n.x);
    Edges2D ezx = edges2D(v0.zx, v1.zx, v2.zx, n.y);
    ivec3 lo = max(ivec3(floor(min(v0, min(v1, v2)) - kSlack)), ivec3(0));
    ivec3 hi = min(ivec3(floor(max(v0, max(v1, v2)) + kSlack)), uGridSize - 1);
    // Tiles are aligned to the grid (so a z tile is exactly one word); the CPU counted them
    // with the same bounds (gpu_voxelizer.cpp tileCount).
    ivec3 t0 = lo / kTile, tn = max(hi / kTile - t0 + 1, ivec3(0));
#ifdef COUNT_TILES
    tileStart[t] = any(lessThan(hi, lo)) ? 0u : uint(tn.x * tn.y * tn.z);
    return;
#endif
    ivec3 ti = t0 + ivec3(int(tile) % tn.x, (int(tile) / tn.x) % tn.y, int(tile) / (tn.x * tn.y));
    lo = max(lo, ti * kTile);
    hi = min(hi, ti * kTile + kTile - 1);
    int wpc = (uGridSize.z + 31) / 32;
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            if (!inside2D(exy, vec2(x, y))) continue;
            uint bits = 0u;
            int word = lo.z / 32;
            for (int z = lo.z; z <= hi.z; ++z) {
                vec3 p = vec3(x, y, z);
                float np = dot(n, p);
                bool hit = (np + d1) * (np + d2) <= 0.0 || abs(np + d1) <= planeSlack ||
                           abs(np + d2) <= planeSlack;
                if (hit && inside2D(eyz, p.yz) && inside2D(ezx, p.zx)) bits |= 1u << uint(z % 32);
                if (z % 32 == 31 || z == hi.z) {
                    if (bits != 0u) atomicOr(words[(y * uGridSize.x + x) * wpc + word], bits);
                    bits = 0u;
                    word++;
                }
            }
        }
}
