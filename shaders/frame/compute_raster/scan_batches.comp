#version 450 core
// One invocation per tile: the counts of the tile's batches become offsets in its list
// (exclusive prefix sums over the batches), the tile's total goes to rasterTileStarts (made
// starts by scan_tiles.comp).
#include "../../common/bindings.h"
#include "bin_lists.glsl"

layout(local_size_x = 256) in;

uniform uint tileCount;
uniform uint batches;

void main() {
    uint tile = gl_GlobalInvocationID.x;
    if (tile >= tileCount) return;
    uint sum = 0u;
    for (uint b = 0u; b < batches; ++b) {
        uint c = rasterBinOffsets[b * tileCount + tile];
        rasterBinOffsets[b * tileCount + tile] = sum;
        sum += c;
    }
    rasterTileStarts[tile] = sum;
}
