// Slice-range bit masks for the 1024 slices (8 RGBA32UI targets x 128 bits) of one
// voxelization pass ([Eisemann06 sec. 2]: the color channels' bits are the column's cells).
#ifndef VEIL_VOXELIZE_BITS_GLSL
#define VEIL_VOXELIZE_BITS_GLSL

// Bits of word `w` (global index) set for slices k0..k1 (inclusive, global).
uint rangeMask(int w, int k0, int k1) {
    int lo = max(k0 - 32 * w, 0), hi = min(k1 - 32 * w, 31);
    if (hi < lo) return 0u;
    uint upper = hi == 31 ? 0xffffffffu : (1u << uint(hi + 1)) - 1u;
    return upper & (0xffffffffu << uint(lo));
}

// Fills the 8 outputs of pass `passIndex` (slices 1024 p .. 1024 p + 1023) with k0..k1.
void writeRange(int passIndex, int k0, int k1, out uvec4 words[8]) {
    for (int t = 0; t < 8; ++t) {
        int w = passIndex * 32 + t * 4;
        words[t] = uvec4(rangeMask(w, k0, k1), rangeMask(w + 1, k0, k1), rangeMask(w + 2, k0, k1),
                         rangeMask(w + 3, k0, k1));
    }
}

#endif
