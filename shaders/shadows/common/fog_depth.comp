#version 450 core
// FogDepthMap (src/shadows/common/fog_depth.h): per light view, the optical depth of the grid
// density volumes along every fog column of the view. Texel (x, y, view * (slices + 1) + k)
// holds the optical depth from the near plane to slice boundary k = 0 .. slices (uniform
// slices of the view's normalized linear depth, boundary 0 = 0), so a receiver at slice
// coordinate fs reads it with linear filtering at fs (fog_depth.glsl) and gets exp(-tau).
//
// The column's centre ray is integrated over the volumes' bounds only, [tIn, tOut], with
// N = slices x uSubsteps midpoint samples of length H = (tOut - tIn) / N, and every boundary
// takes the sum up to it (the sample across it in proportion). So the samples start and end
// at the bounds, and their length follows the media's extent along the column, not the
// view's depth range. A midpoint sum whose sample phase is fixed by the near plane and whose
// samples are slice / uSubsteps long errs at every density face by up to sigma x that length
// / 2, the same on every column of a directional light (the faces of a slab are planes): the
// fog slab under a floor 20 wide came out 0.5 % dark at tau 1.414 and 1.3 % at tau 3, more
// in deeper views. Here the error
// of the optical depth is bounded by the midpoint rule's: for a density that is continuous
// inside the bounds (trilinear between voxels, whose faces the bounds enclose) and piecewise
// smooth, at most |jump in d sigma / ds| x H^2 / 8 per kink of the profile along the ray (a
// trilinear ramp of length w along the ray has two kinks of sigma / w each; H <= w), plus
// the curvature term (tOut - tIn) x max |sigma''| x H^2 / 24; a jump of sigma strictly inside
// the bounds (none for grids) would add sigma x H / 2. For the fog slab of
// tests/gl/shadow_fog_depth_test.cpp (bounds 2.3 long along the ray, H = 0.0044 at the
// defaults, ramps 0.07 long): 4 kinks x sigma x 3.4e-5, far below 1 % of T.
//
// A dispatch marches the samples [uSamples.x, uSamples.y) of every column and keeps the sum
// and the next boundary in uState for the next dispatch (FogDepthMap::run() splits the N
// samples in dispatches of kSamplesPerDispatch): Mesa's llvmpipe ends all loops of one
// invocation after 65535 iterations, and fog_slices x fog_substeps reaches 65536 samples.
#include "views.glsl"
#include "../../volume/volume_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_IMG_VOLUME_LIGHT, r32f) uniform writeonly image3D uTau;
// Per column: the optical depth summed so far and the next boundary to store (as a float).
layout(binding = VEIL_IMG_VOLUME_LIGHT_STATE, rg32f) uniform image2D uState;

uniform int shadowView;
uniform int uSlices;
uniform int uSubsteps;
uniform int uColumns;
uniform ivec2 rows; // column rows [rows.x, rows.y) of this dispatch (bands, the .cpp)
uniform ivec2 uSamples; // the samples [x, y) of the column's N this dispatch marches
uniform mat4 uClipToWorld; // inverse of the view's viewProjection

vec3 unproject(vec2 ndc, float z) {
    vec4 w = uClipToWorld * vec4(ndc, z, 1.0);
    return w.xyz / w.w;
}

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, rows.x);
    if (c.x >= uColumns || c.y >= rows.y) return;
    vec2 ndc = (vec2(c) + 0.5) / float(uColumns) * 2.0 - 1.0;
    // The column's centre ray between the near and far planes; the normalized linear depth is
    // linear in world position along it (ortho and perspective alike).
    vec3 A = unproject(ndc, -1.0), B = unproject(ndc, 1.0);
    float tA = shadowViewDepth(shadowView, A), tB = shadowViewDepth(shadowView, B);
    vec3 perT = (B - A) / (tB - tA);
    vec3 origin = A - perT * tA; // normalized depth 0
    float tIn = 1e30, tOut = -1e30;
    for (int i = 0; i < volumeCount; ++i) {
        vec2 iv = volumeBoxInterval(i, origin, perT);
        if (iv.x < iv.y) {
            tIn = min(tIn, iv.x);
            tOut = max(tOut, iv.y);
        }
    }
    tIn = max(tIn, 0.0);
    tOut = min(tOut, 1.0);
    int z0 = shadowView * (uSlices + 1);
    float dt = 1.0 / float(uSlices), worldPerT = length(perT);
    int n = uSlices * uSubsteps;
    bool first = uSamples.x == 0, last = uSamples.y >= n;
    float tau = 0.0;
    int k = 0; // the next boundary to store
    if (!first) {
        vec2 state = imageLoad(uState, c).xy;
        tau = state.x;
        k = int(state.y);
    }
    if (tIn < tOut) {
        float H = (tOut - tIn) / float(n);
        if (first)
            for (; k <= uSlices && float(k) * dt <= tIn; ++k) imageStore(uTau, ivec3(c, z0 + k), vec4(0.0));
        for (int m = uSamples.x; m < min(uSamples.y, n); ++m) {
            float s0 = tIn + float(m) * H;
            float sigma = volumeExtinction(origin + perT * (s0 + 0.5 * H)) * worldPerT;
            for (; k <= uSlices && float(k) * dt < s0 + H; ++k)
                imageStore(uTau, ivec3(c, z0 + k), vec4(tau + sigma * (float(k) * dt - s0)));
            tau += sigma * H;
        }
    }
    if (last)
        for (; k <= uSlices; ++k) imageStore(uTau, ivec3(c, z0 + k), vec4(tau));
    else
        imageStore(uState, c, vec4(tau, float(k), 0.0, 0.0));
}
