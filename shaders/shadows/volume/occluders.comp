#version 450 core
// [Eisemann06 sec. 3.2] "caster culling" input: the farthest opaque-map depth (normalized linear, as
// stored by DepthMaps) over each grid column's texels, widened by one texel on every side, so
// that a caster whose nearest depth is beyond it is hidden from the light by other casters.
#include "grid.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_SHADOW3) uniform sampler2DArray opaqueDepth; // compare mode off
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_OCCLUDERS) writeonly buffer Occluders {
    float occluderFar[];
};
uniform int slot;
uniform int mapSize;

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(c, ivec2(uGrid)))) return;
    int v = uSlotView[slot];
    ivec2 lo = max(c * mapSize / uGrid - 1, ivec2(0));
    ivec2 hi = min(((c + 1) * mapSize + uGrid - 1) / uGrid, ivec2(mapSize - 1));
    float farthest = 0.0;
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
            farthest = max(farthest, texelFetch(opaqueDepth, ivec3(x, y, v), 0).r);
    occluderFar[gridColumn(slot, c)] = farthest;
}
