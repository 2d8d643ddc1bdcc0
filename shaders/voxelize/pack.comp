#version 450
// Copies one pass's 8 RGBA32UI targets (128 x 8 = 1024 slices) into the column-contiguous
// slice-map SSBO (layout: src/voxelize/slice_map.h), words 32 p .. 32 p + 31 of each column.
#include "../common/bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_VOX0 + 0) uniform usampler2D uT0;
layout(binding = VEIL_TEX_VOX0 + 1) uniform usampler2D uT1;
layout(binding = VEIL_TEX_VOX0 + 2) uniform usampler2D uT2;
layout(binding = VEIL_TEX_VOX0 + 3) uniform usampler2D uT3;
layout(binding = VEIL_TEX_VOX0 + 4) uniform usampler2D uT4;
layout(binding = VEIL_TEX_VOX0 + 5) uniform usampler2D uT5;
layout(binding = VEIL_TEX_VOX0 + 6) uniform usampler2D uT6;
layout(binding = VEIL_TEX_VOX0 + 7) uniform usampler2D uT7;
layout(std430, binding = VEIL_SSBO_VOX_WORDS) buffer Words { uint words[]; };
uniform ivec3 uGridSize;
uniform int uPass;
// First word of this slice map in the SSBO (0 = the voxelizer's single map; the shadow
// technique transmittance-slicemap packs one map per light view and material class).
uniform uint uWordOffset;

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    if (c.x >= uGridSize.x || c.y >= uGridSize.y) return;
    int wpc = (uGridSize.z + 31) / 32, base = (c.y * uGridSize.x + c.x) * wpc;
    uvec4 t[8] = uvec4[8](texelFetch(uT0, c, 0), texelFetch(uT1, c, 0), texelFetch(uT2, c, 0),
                          texelFetch(uT3, c, 0), texelFetch(uT4, c, 0), texelFetch(uT5, c, 0),
                          texelFetch(uT6, c, 0), texelFetch(uT7, c, 0));
    for (int i = 0; i < 32; ++i) {
        int w = uPass * 32 + i;
        if (w >= wpc) break;
        uint v = t[i / 4][i % 4];
        // Slices past the grid's count (last word) stay clear: solid passes set to the end.
        if (w == wpc - 1 && uGridSize.z % 32 != 0) v &= (1u << uint(uGridSize.z % 32)) - 1u;
        words[uWordOffset + uint(base + w)] = v;
    }
}
