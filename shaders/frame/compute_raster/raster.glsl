// The compute rasterizer's data (src/frame/stages/compute_raster.h), after
// [Laine11 sec. 3-4]: triangle setup writes one record per input triangle (and more, from a
// second region, where clipping splits it), binning builds per-tile lists of input triangles
// in submission order, fine rasterization runs one workgroup per tile. Included after
// "veil:raster_surface" or "veil:raster_layout" (SURFACE_ATTRIBUTES, SURFACE_RECORD_VEC4S).
#include "../../common/bindings.h"

#define RASTER_TILE 16    // tile side in pixels (one fine-raster workgroup, one pixel each)
#define RASTER_BATCH 256  // input triangles per bin batch (a tile's list is ordered per batch)
#define RASTER_SUBPIXEL 256 // 8 sub-pixel bits, as the hardware snaps vertices

// A screen-space triangle: vertices snapped to 1/RASTER_SUBPIXEL pixel in window coordinates
// (y up, GL's), counter-clockwise (positive area) after setup swapped them where needed.
struct RasterTriangle {
    ivec4 x;      // xyz: the vertices' fixed-point x; w: object index
    ivec4 y;      // xyz: fixed-point y; w (first record of an input triangle): its subtriangles
                  // (bits 0-2) and the record of the second one (bits 3-30)
    vec4 z;       // xyz: window depth [0, 1]
    vec4 invW;    // xyz: 1 / w_clip (perspective-correct interpolation)
    ivec4 bounds; // pixels whose centres it may cover, x0 y0 x1 y1 inclusive (x0 > x1: none)
};

layout(std430, binding = VEIL_SSBO_RASTER_TRIANGLES) restrict buffer RasterTriangles {
    RasterTriangle rasterTriangles[];
};
// Per record, the vertices' attributes (3 x SURFACE_ATTRIBUTES floats), apart: coverage reads
// the records alone, and each buffer stays within a driver's SSBO size limit (llvmpipe: 128 MiB).
layout(std430, binding = VEIL_SSBO_RASTER_ATTRIBUTES) restrict buffer RasterAttributes {
    float rasterAttributes[];
};
layout(std430, binding = VEIL_SSBO_RASTER_COUNTERS) restrict buffer RasterCounters {
    uint rasterExtraRecords; // records of further subtriangles requested (may exceed capacity)
    uint rasterPairs;        // (tile, triangle) entries of all lists (the bin scan's total)
    uint rasterPad0, rasterPad1;
    vec4 rasterObjects[];    // SURFACE_RECORD_VEC4S per object: its material
};
