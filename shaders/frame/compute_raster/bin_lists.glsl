// The bins of the compute rasterizer [Laine11 sec. 4.2-4.3]: per tile, the input triangles
// that may touch it, as one list ordered by batch (RASTER_BATCH consecutive input triangles)
// whose segments the fine stage sorts back into submission order.
//   rasterTileStarts[t]          first entry of tile t's list (exclusive scan of the tiles)
//   rasterBinOffsets[b * T + t]  count of batch b's triangles in tile t (bin.comp, counting),
//                                then their offset in the tile's list (scan_batches.comp), then
//                                that offset plus the count (bin.comp, filling): the end of
//                                batch b's segment = the start of batch b + 1's
//   rasterTileLists[]            input triangle indices
layout(std430, binding = VEIL_SSBO_RASTER_TILE_STARTS) restrict buffer RasterTileStarts {
    uint rasterTileStarts[];
};
layout(std430, binding = VEIL_SSBO_RASTER_BIN_OFFSETS) restrict buffer RasterBinOffsets {
    uint rasterBinOffsets[];
};
layout(std430, binding = VEIL_SSBO_RASTER_TILE_LISTS) restrict buffer RasterTileLists {
    uint rasterTileLists[];
};
