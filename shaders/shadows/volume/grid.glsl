// The light-space grid of the `volume` technique's culling and clamping [Eisemann06 sec. 3.2]: for
// each light slot with one view (directional, spot), `uGrid` x `uGrid` columns over the view's
// map and `uSlices` slices of its normalized linear depth (views.glsl), 32 slices per word,
// column-contiguous like src/voxelize/slice_map.h.
#include "../common/views.glsl"

uniform int uGrid;
uniform int uSlices;
uniform int uSlotView[VEIL_MAX_LIGHTS]; // the slot's view, -1 = not culled or clamped

int gridWords() { return (uSlices + 31) / 32; }
int gridColumn(int slot, ivec2 c) { return (slot * uGrid + c.y) * uGrid + c.x; }
