#version 450
// Three-axis voxelization: ORs the x- and y-view maps into the z-view map (the grid). The
// x view's columns are (y, z) with slices along x; the y view's are (z, x) with slices along
// y (src/voxelize/slice_map.cpp axisView). One thread per (column, word) of the grid.
#include "../common/bindings.h"
layout(local_size_x = 64) in;
layout(std430, binding = VEIL_SSBO_VOX_WORDS) buffer Words { uint words[]; };
layout(std430, binding = VEIL_SSBO_VOX_AXIS0) readonly buffer AxisX { uint xWords[]; };
layout(std430, binding = VEIL_SSBO_VOX_AXIS0 + 1) readonly buffer AxisY { uint yWords[]; };
uniform ivec3 uGridSize; // nx, ny, nz

bool bitAt(int wordIndex, int bit, bool fromX) {
    uint w = fromX ? xWords[wordIndex] : yWords[wordIndex];
    return ((w >> uint(bit)) & 1u) != 0u;
}

void main() {
    int nx = uGridSize.x, ny = uGridSize.y, nz = uGridSize.z;
    int wpc = (nz + 31) / 32, wpcX = (nx + 31) / 32, wpcY = (ny + 31) / 32;
    int id = int(gl_GlobalInvocationID.x);
    if (id >= nx * ny * wpc) return;
    int w = id % wpc, col = id / wpc, x = col % nx, y = col / nx;
    uint v = words[id];
    for (int b = 0; b < 32; ++b) {
        int z = w * 32 + b;
        if (z >= nz) break;
        if (bitAt((z * ny + y) * wpcX + x / 32, x % 32, true) ||
            bitAt((x * nz + z) * wpcY + y / 32, y % 32, false))
            v |= 1u << uint(b);
    }
    words[id] = v;
}
