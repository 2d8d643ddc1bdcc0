#version 450 core
// Binning [Laine11 sec. 4.2-4.3], one invocation per input triangle: the tiles its
// subtriangles' pixel bounds overlap. BIN_FILL undefined: counts per (batch, tile); defined:
// appends the triangle to each tile's segment of its batch (order inside a segment is
// arbitrary: fine.comp sorts it).
#include "veil:raster_layout"
#include "raster.glsl"
#include "bin_lists.glsl"

layout(local_size_x = 256) in;

uniform uint triangleCount;
uniform ivec2 tiles;         // tiles per row, rows
uniform uint listCapacity;   // entries rasterTileLists holds (BIN_FILL)

void main() {
    uint tri = gl_GlobalInvocationID.x;
    if (tri >= triangleCount) return;
    RasterTriangle t = rasterTriangles[tri];
    uint subtriangles = uint(t.y.w) & 7u;
    if (subtriangles == 0u) return;
    ivec4 b = t.bounds;
    uint extra = uint(t.y.w) >> 3;
    for (uint k = 1u; k < subtriangles; ++k) {
        ivec4 e = rasterTriangles[extra + k - 1u].bounds;
        if (e.x > e.z) continue;
        b = b.x > b.z ? e : ivec4(min(b.xy, e.xy), max(b.zw, e.zw));
    }
    if (b.x > b.z || b.y > b.w) return;
    ivec4 tb = b / RASTER_TILE; // bounds are >= 0
    uint tileCount = uint(tiles.x * tiles.y);
    uint batchBase = (tri / RASTER_BATCH) * tileCount;
    for (int ty = tb.y; ty <= tb.w; ++ty)
        for (int tx = tb.x; tx <= tb.z; ++tx) {
            uint tile = uint(ty * tiles.x + tx);
#ifdef BIN_FILL
            uint at = rasterTileStarts[tile] + atomicAdd(rasterBinOffsets[batchBase + tile], 1u);
            if (at < listCapacity) rasterTileLists[at] = tri;
#else
            atomicAdd(rasterBinOffsets[batchBase + tile], 1u);
#endif
        }
}
