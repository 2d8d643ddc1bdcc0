#version 450 core
// `transmittance-slicemap` (src/shadows/transmittance_slicemap): the semi-transparent casters
// into one light view's slice map [Eisemann06 sec. 2 and 3], drawn by the frame's caster draw with
// frame/mesh.vert and the view's matrix. The slice coordinate is the view's normalized linear
// depth (views.glsl: ortho = window depth, perspective = linear eye depth, the convention of
// src/voxelize/slice_map.h with perspective = true), so slices have equal thickness along
// every light ray.
// Defines:
//   DEPTH_PASS    local slicing's range pass ([Eisemann06 sec. 2.2], as voxelize.frag): (t, -t) into an
//                 RG32F layer with GL_MIN blending = per-column near and far of the casters
//   LOCAL         slices subdivide the column's [near, far] from the range pass
//   CONSERVATIVE  "conservative" method, depth part only: every slice of the surface's depth
//                 range over the texel (from the depth derivatives) instead of the one slice at
//                 the texel centre ("raster", [Eisemann06] as published)
// Otherwise: one fragment's bit mask (voxelize/bits.glsl writeRange) in the 8 RGBA32UI
// targets of geometry pass uPass (slices 1024 p .. 1024 p + 1023), OR-ed by the logic op,
// for the fragments whose material falls in class uClass.
#include "../common/views.glsl"
#include "../../frame/material.glsl"
#include "../../voxelize/bits.glsl"

uniform int shadowView;
uniform int uSlices;
uniform int uPass;
uniform int uClass;
uniform int uClasses;
uniform vec3 uClassT[3]; // per class: transmittance per crossing surface (C++ chooses them)

#ifdef LOCAL
layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray uRange;
#endif

#ifdef DEPTH_PASS
layout(location = 0) out vec2 oRange;
#else
layout(location = 0) out uvec4 oWords[8];
#endif

// The class whose transmittance is nearest (in absorbance, -log T) to this material's.
int materialClass(vec3 t) {
    vec3 a = -log(max(t, vec3(1e-4)));
    int best = 0;
    float bestD = 1e30;
    for (int c = 0; c < uClasses; ++c) {
        vec3 d = a + log(max(uClassT[c], vec3(1e-4)));
        float dd = dot(d, d);
        if (dd < bestD) {
            bestD = dd;
            best = c;
        }
    }
    return best;
}

void main() {
    // Particles: nothing where the billboard's coverage falls to zero.
    if (surfaceCoverage() < 1.0 / 255.0) discard;
    float t = shadowViewDepth(shadowView, vWorldPos);
#ifdef DEPTH_PASS
    oRange = vec2(t, -t);
#else
    if (materialClass(surfaceTransmittance(coverage)) != uClass) discard;
    vec2 r = vec2(0.0, 1.0);
#ifdef LOCAL
    r = texelFetch(uRange, ivec3(ivec2(gl_FragCoord.xy), shadowView), 0).xy * vec2(1.0, -1.0);
    r.y = max(r.y, r.x + 1e-7);
#endif
    float scale = float(uSlices) / (r.y - r.x);
#ifdef CONSERVATIVE
    float dt = 0.5 * (abs(dFdx(t)) + abs(dFdy(t)));
    int k0 = clamp(int(floor((t - dt - r.x) * scale)), 0, uSlices - 1);
    int k1 = clamp(int(floor((t + dt - r.x) * scale)), 0, uSlices - 1);
#else
    int k0 = clamp(int(floor((t - r.x) * scale)), 0, uSlices - 1), k1 = k0;
#endif
    writeRange(uPass, k0, k1, oWords);
#endif
}
