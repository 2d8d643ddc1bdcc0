// Slice counts of the light-space slice maps of `transmittance-slicemap`
// (src/shadows/transmittance_slicemap): one map per (light view, material class), each the
// column-contiguous layout of src/voxelize/slice_map.h (32 slices per word, bit b of word w
// = slice 32 w + b), packed one after another in one SSBO:
//     word index = ((view * classes + class) * columns + column) * wordsPerColumn + w.
// [Eisemann06 sec. 3]: the attenuation at a receiver is prod_c T_c^(n_c), n_c = the set slices of
// class c in front of the receiver's slice, counted with bitCount over masked words (the
// same masks as SliceMap::countOccupied and slice_map.glsl's smCountOccupied).
#ifndef VEIL_SHADOWS_SLICEMAP_SLICES_GLSL
#define VEIL_SHADOWS_SLICEMAP_SLICES_GLSL

#include "../../common/bindings.h"

layout(std430, binding = VEIL_SSBO_SHADOW_SLICES) readonly buffer SlmWords { uint slmWords[]; };

// Set slices 0..s1 (inclusive) of the column whose first word is `base`: whole words, then
// the last word masked to its bits 0..s1 % 32.
int slmCountPrefix(uint base, int s1) {
    if (s1 < 0) return 0;
    int last = s1 / 32, n = 0;
    for (int w = 0; w < last; ++w)
        n += bitCount(slmWords[base + uint(w)]);
    uint m = s1 % 32 == 31 ? 0xffffffffu : (1u << uint(s1 % 32 + 1)) - 1u;
    return n + bitCount(slmWords[base + uint(last)] & m);
}

// prod_c T_c^(n_c) over the `classes` classes of view `view` for column `column` and the
// slices 0..s1 in front of the receiver.
vec3 slmAttenuation(int view, int classes, int columns, int wordsPerColumn, int column, int s1,
                    vec3 classT[3]) {
    vec3 t = vec3(1.0);
    for (int c = 0; c < classes; ++c) {
        uint base = (uint(view * classes + c) * uint(columns) + uint(column)) * uint(wordsPerColumn);
        int n = slmCountPrefix(base, s1);
        if (n > 0) t *= pow(classT[c], vec3(float(n)));
    }
    return t;
}

#endif
