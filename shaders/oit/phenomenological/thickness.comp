#version 450 core
// OIT `phenomenological` with volume refraction: thickness of the transparent media along each
// pixel's eye ray from the front-face and back-face slice maps of the PHEN_THICKNESS pass
// ([Eisemann06 sec. 3], "volume computation"; 512 slices of length (far - near) / 512 uniform in view
// depth). The walk goes from near to far one slice at a time (empty words at once):
//   front only   enter the medium; the entry slice counts 1/2
//   back only    leave it; the exit slice counts 1/2 (a back face while outside: ignored)
//   both         ambiguous slice [Eisemann06 Fig. 9]: counts as a whole slice inside; the state after it
//                is unknown until the next unambiguous slice: a back face there means the empty
//                slices in between were inside (added), a front face that they were outside
//                (dropped); between two ambiguous slices they are added ([Eisemann06]: "in practice we
//                decide to include them")
// A medium still open after the last slice (a lone camera-facing plane, or a mesh cut by the
// opaque depth or the far plane) counts 0: planes are thin surfaces.
// Output (RG32F): h = thickness, n = number of front-face bits (the media entered along the ray:
// each front face applies Beer-Lambert over h / n, so the whole path absorbs once).
// The thickness is exact to within one slice length for closed meshes whose faces fall in
// distinct slices.
#include "../../common/camera.glsl"
#include "../../common/region.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = VEIL_PHEN_TEX_SLICES + 0) uniform usampler2D phenFront0;
layout(binding = VEIL_PHEN_TEX_SLICES + 1) uniform usampler2D phenFront1;
layout(binding = VEIL_PHEN_TEX_SLICES + 2) uniform usampler2D phenFront2;
layout(binding = VEIL_PHEN_TEX_SLICES + 3) uniform usampler2D phenFront3;
layout(binding = VEIL_PHEN_TEX_SLICES + 4) uniform usampler2D phenBack0;
layout(binding = VEIL_PHEN_TEX_SLICES + 5) uniform usampler2D phenBack1;
layout(binding = VEIL_PHEN_TEX_SLICES + 6) uniform usampler2D phenBack2;
layout(binding = VEIL_PHEN_TEX_SLICES + 7) uniform usampler2D phenBack3;
layout(binding = VEIL_IMG_OUTPUT, rg32f) uniform writeonly image2D thicknessOut;

const int OUTSIDE = 0, INSIDE = 1, UNKNOWN = 2;

void main() {
    ivec2 size = textureSize(phenFront0, 0);
    ivec2 p;
    if (!regionPixel(size, p)) return;
    uvec4 front[4] = uvec4[4](texelFetch(phenFront0, p, 0), texelFetch(phenFront1, p, 0),
                              texelFetch(phenFront2, p, 0), texelFetch(phenFront3, p, 0));
    uvec4 back[4] = uvec4[4](texelFetch(phenBack0, p, 0), texelFetch(phenBack1, p, 0),
                             texelFetch(phenBack2, p, 0), texelFetch(phenBack3, p, 0));
    float sliceLength = (camera.viewport.w - camera.viewport.z) / 512.0;
    int state = OUTSIDE;
    float total = 0.0;   // closed (or resolved) slices inside, in slices
    float run = 0.0;     // slices inside the medium entered last (not yet closed)
    float pending = 0.0; // empty slices after an ambiguous one (state UNKNOWN)
    int fronts = 0;
    for (int w = 0; w < 16; ++w) {
        uint f = front[w >> 2][w & 3], b = back[w >> 2][w & 3];
        fronts += bitCount(f);
        if ((f | b) == 0u) {
            if (state == INSIDE) run += 32.0;
            if (state == UNKNOWN) pending += 32.0;
            continue;
        }
        for (int bit = 0; bit < 32; ++bit) {
            bool isFront = ((f >> uint(bit)) & 1u) != 0u;
            bool isBack = ((b >> uint(bit)) & 1u) != 0u;
            if (isFront && isBack) {
                // Ambiguous: the whole slice is inside, what follows is unknown.
                if (state == INSIDE) total += run;
                if (state == UNKNOWN) total += pending;
                total += 1.0;
                run = 0.0;
                pending = 0.0;
                state = UNKNOWN;
            } else if (isFront) {
                if (state == INSIDE) {
                    run += 1.0; // nested or overlapping media: one bit cannot count them
                } else {
                    pending = 0.0; // after an ambiguous slice: we were outside
                    run = 0.5;
                    state = INSIDE;
                }
            } else if (isBack) {
                if (state == INSIDE) total += run + 0.5;
                if (state == UNKNOWN) total += pending + 0.5; // we were inside
                run = 0.0;
                pending = 0.0;
                state = OUTSIDE;
            } else {
                if (state == INSIDE) run += 1.0;
                if (state == UNKNOWN) pending += 1.0;
            }
        }
    }
    imageStore(thicknessOut, p, vec4(total * sliceLength, float(fronts), 0.0, 0.0));
}
