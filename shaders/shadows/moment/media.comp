#version 450 core
// The density volumes' absorbance added into the moment maps (issue: "the density field's
// absorbance written into the same map by a compute pass that marches the volumes toward the
// light"): one invocation per texel and view; the texel's ray from the view's near to its far
// plane is clipped to the volumes' bounds and marched in `steps` midpoint steps; each step of
// extinction sigma and length dt adds absorbance sigma dt at its depth, exactly as a surface of
// that absorbance would [Munstermann18 sec. 3.1]. Extinction is grey, so the media keep their own
// scalar b0 (the absorbance map's alpha) and moments (the media moment map): mixed into the
// surfaces' mean-absorbance moments, the grey fog would dilute a pane's colour in the shaft
// under it (src/shadows/moment/moment.h, "Colour").
#include "../../volume/volume_common.glsl"
#include "../common/views.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = 1, rgba32f) uniform image2DArray absorbanceImage; // alpha: media b0
layout(binding = 2, rgba32f) uniform image2DArray mediaMomentImage;

uniform mat4 clipToWorld[VEIL_MAX_SHADOW_VIEWS]; // inverse view projection per view
uniform int firstLayer;                          // views [firstLayer, firstLayer + gl_NumWorkGroups.z)
uniform int steps;
uniform ivec2 rows; // texel rows [rows.x, rows.y) of this dispatch (moment.cpp, banded runs)
uniform int skipEmptyLeaves; // media_skip_empty

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID.x, rows.x + int(gl_GlobalInvocationID.y),
                    firstLayer + int(gl_GlobalInvocationID.z));
    ivec2 size = imageSize(absorbanceImage).xy;
    if (c.x >= size.x || c.y >= rows.y) return;
    int v = c.z;
    vec2 ndc = (vec2(c.xy) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 a = clipToWorld[v] * vec4(ndc, -1.0, 1.0), b = clipToWorld[v] * vec4(ndc, 1.0, 1.0);
    vec3 pNear = a.xyz / a.w, pFar = b.xyz / b.w; // at the view's near and far planes
    float len = length(pFar - pNear);
    vec3 rd = (pFar - pNear) / max(len, 1e-20);
    float t0 = 1e30, t1 = -1e30;
    for (int i = 0; i < volumeCount; ++i) {
        vec2 iv = volumeBoxInterval(i, pNear, rd);
        if (iv.x < iv.y) {
            t0 = min(t0, iv.x);
            t1 = max(t1, iv.y);
        }
    }
    t0 = max(t0, 0.0);
    t1 = min(t1, len);
    if (!(t0 < t1)) return;
    float dt = (t1 - t0) / float(steps);
    float sumB0 = 0.0;
    vec4 sumB = vec4(0.0);
    // Steps in leaves that are empty in every volume add nothing, so they are jumped over to the
    // first step past the leaf's exit (as light_transmittance.comp does): the same sums as
    // visiting every step, at a fraction of the cost on sparse smoke (on llvmpipe this pass
    // took 3.7 s of fog.json's frame: 2048^2 texels x 64 steps).
    for (int s = 0; s < steps; ++s) {
        float t = t0 + (float(s) + 0.5) * dt;
        bool empty;
        float sigma = volumeExtinctionOrEmpty(pNear + rd * t, empty);
        if (empty && skipEmptyLeaves != 0) {
            s = max(s, firstStepPast(t, volumesLeafExit(pNear + rd * t, rd), t0, dt, 0.5) - 1);
            continue;
        }
        if (sigma <= 0.0) continue;
        float absorbance = sigma * dt;
        float z = clamp(t / len, 0.0, 1.0) * 2.0 - 1.0; // linear depth: t / len along the axis
        float z2 = z * z;
        sumB0 += absorbance;
        sumB += absorbance * vec4(z, z2, z2 * z, z2 * z2);
    }
    if (sumB0 <= 0.0) return;
    imageStore(absorbanceImage, c, imageLoad(absorbanceImage, c) + vec4(0.0, 0.0, 0.0, sumB0));
    imageStore(mediaMomentImage, c, sumB);
}
