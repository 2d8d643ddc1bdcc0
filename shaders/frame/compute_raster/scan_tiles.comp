#version 450 core
// One workgroup: the tiles' totals become the starts of their lists (exclusive prefix sum),
// the sum of all goes to rasterPairs (the host sizes rasterTileLists from it).
#include "veil:raster_layout"
#include "raster.glsl"
#include "bin_lists.glsl"

#define SCAN_THREADS 1024
layout(local_size_x = SCAN_THREADS) in;

uniform uint tileCount;

shared uint partial[SCAN_THREADS];

void main() {
    uint i = gl_LocalInvocationID.x;
    uint chunk = (tileCount + SCAN_THREADS - 1u) / SCAN_THREADS;
    uint first = i * chunk, last = min(first + chunk, tileCount);
    uint sum = 0u;
    for (uint t = first; t < last; ++t) sum += rasterTileStarts[t];
    partial[i] = sum;
    barrier();
    // Inclusive Hillis-Steele scan of the chunks' sums.
    for (uint step = 1u; step < SCAN_THREADS; step <<= 1) {
        uint add = i >= step ? partial[i - step] : 0u;
        barrier();
        partial[i] += add;
        barrier();
    }
    uint running = partial[i] - sum;
    for (uint t = first; t < last; ++t) {
        uint c = rasterTileStarts[t];
        rasterTileStarts[t] = running;
        running += c;
    }
    if (i == SCAN_THREADS - 1u) rasterPairs = partial[i];
}
