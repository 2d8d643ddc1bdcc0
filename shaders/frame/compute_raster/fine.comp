#version 450 core
// Fine rasterization [Laine11 sec. 4.4]: one workgroup per 16 x 16 tile, one invocation per
// pixel, which alone writes its pixel's accumulation while the workgroup runs. The tile's list
// is taken a batch segment at a time into shared memory, sorted back into submission order
// there (a segment holds at most RASTER_BATCH input triangles), and walked in that order, so
// that every pixel sees its fragments in the order the hardware would blend them.
// Per pixel and triangle, as GL rasterizes (docs/oit.md "Compute rasterizer"): coverage of the
// pixel centre by exact fixed-point edge functions (8 sub-pixel bits; double precision holds
// their products exactly) with the tie rule for GL's lower-left origin (a centre on an edge
// belongs to the triangle whose edge is a left or bottom one), the window depth interpolated
// linearly in screen space and tested GL_LESS against the opaque depth, the attributes
// interpolated perspective-correctly, then the hardware path's surface shading
// (frame/transparent_surface.glsl) and the technique's oitEmit() (OIT_COMPUTE: its targets
// as images).
#include "veil:raster_surface"
#include "raster.glsl"
#include "bin_lists.glsl"

layout(local_size_x = RASTER_TILE, local_size_y = RASTER_TILE) in;

layout(binding = VEIL_TEX_DEPTH) uniform sampler2D rasterOpaqueDepth;
uniform ivec2 tiles;      // tiles per row, rows
uniform ivec2 firstTile;  // the dispatch's first tile (a refinement region)
uniform ivec4 region;     // pixels written, x0 y0 x1 y1 (exclusive)
uniform uint batches;

shared uint segment[RASTER_BATCH];
shared uint ordered[RASTER_BATCH];

// Edge i from (ax, ay) to (bx, by) of a counter-clockwise triangle at centre c (fixed point,
// exact): > 0 inside. A centre on the edge is inside for left edges (going down) and bottom
// edges (horizontal, going right), outside for the others: the tie rule of GL's hardware
// rasterizers with the lower-left window origin, so that a centre on an edge shared by two
// triangles is covered once.
bool inside(ivec2 a, ivec2 b, dvec2 c, out double e) {
    e = double(b.x - a.x) * (c.y - double(a.y)) - double(b.y - a.y) * (c.x - double(a.x));
    if (e != 0.0lf) return e > 0.0lf;
    return b.y < a.y || (b.y == a.y && b.x > a.x);
}

void shadeTriangle(uint record, ivec2 pixel, dvec2 centre, float opaqueDepth) {
    ivec4 bounds = rasterTriangles[record].bounds;
    if (any(lessThan(pixel, bounds.xy)) || any(greaterThan(pixel, bounds.zw))) return;
    RasterTriangle t = rasterTriangles[record];
    ivec2 v0 = ivec2(t.x.x, t.y.x), v1 = ivec2(t.x.y, t.y.y), v2 = ivec2(t.x.z, t.y.z);
    double e0, e1, e2;
    if (!inside(v0, v1, centre, e0) || !inside(v1, v2, centre, e1) ||
        !inside(v2, v0, centre, e2))
        return;
    // Screen-space barycentrics: vertex k's weight is the edge opposite it over the area.
    double area = e0 + e1 + e2;
    vec3 l = vec3(dvec3(e1, e2, e0) / area);
    float depth = dot(l, t.z.xyz);
    if (!(depth < opaqueDepth)) return;
    vec3 p = l * t.invW.xyz;
    p /= p.x + p.y + p.z;
    float a[SURFACE_ATTRIBUTES];
    uint base = record * uint(3 * SURFACE_ATTRIBUTES);
    for (uint k = 0u; k < uint(SURFACE_ATTRIBUTES); ++k)
        a[k] = p.x * rasterAttributes[base + k] +
               p.y * rasterAttributes[base + SURFACE_ATTRIBUTES + k] +
               p.z * rasterAttributes[base + 2 * SURFACE_ATTRIBUTES + k];
    vec4 material[SURFACE_RECORD_VEC4S];
    uint object = uint(t.x.w);
    for (int i = 0; i < SURFACE_RECORD_VEC4S; ++i)
        material[i] = rasterObjects[object * SURFACE_RECORD_VEC4S + uint(i)];
    surfaceLoad(material, a);
    OitFragment f;
    if (!transparentFragment(f)) return;
    oitPixel = pixel;
    oitWindowDepth = depth;
    oitEmit(f);
}

void main() {
    ivec2 tile = ivec2(gl_WorkGroupID.xy) + firstTile;
    uint tileIndex = uint(tile.y * tiles.x + tile.x);
    uint tileCount = uint(tiles.x * tiles.y);
    ivec2 pixel = tile * RASTER_TILE + ivec2(gl_LocalInvocationID.xy);
    bool mine = all(greaterThanEqual(pixel, region.xy)) && all(lessThan(pixel, region.zw));
    float opaqueDepth = mine ? texelFetch(rasterOpaqueDepth, pixel, 0).r : -1.0;
    dvec2 centre = dvec2(pixel * RASTER_SUBPIXEL + RASTER_SUBPIXEL / 2);
    uint lane = gl_LocalInvocationIndex;
    uint start = rasterTileStarts[tileIndex];
    for (uint b = 0u; b < batches; ++b) {
        uint end = rasterTileStarts[tileIndex] + rasterBinOffsets[b * tileCount + tileIndex];
        uint n = end - start;
        if (n == 0u) continue;
        if (lane < n) segment[lane] = rasterTileLists[start + lane];
        barrier();
        // Submission order: each entry's rank among the segment's (distinct) indices.
        if (lane < n) {
            uint key = segment[lane], rank = 0u;
            for (uint j = 0u; j < n; ++j) rank += segment[j] < key ? 1u : 0u;
            ordered[rank] = key;
        }
        barrier();
        if (mine) {
            for (uint k = 0u; k < n; ++k) {
                uint tri = ordered[k];
                uint meta = uint(rasterTriangles[tri].y.w);
                uint subtriangles = meta & 7u;
                shadeTriangle(tri, pixel, centre, opaqueDepth);
                uint extra = meta >> 3;
                for (uint s = 1u; s < subtriangles; ++s)
                    shadeTriangle(extra + s - 1u, pixel, centre, opaqueDepth);
            }
        }
        barrier();
        start = end;
    }
}
