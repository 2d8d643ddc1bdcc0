#version 450 core
// AO step 3: the obscurance estimator of Scalable Ambient Obscurance (McGuire, Mara &
// Luebke, HPG 2012; [Mara16] family), per pixel C with camera-space position P_C and
// normal n_C reconstructed from the z pyramid:
//   A(C) = max(0, 1 - (2 sigma / s) sum_i H(r^2 - v_i.v_i) max(0, v_i.n_C - beta z_C)
//                                        / (v_i.v_i + epsilon))^k,      v_i = Q_i - P_C,
// over s samples Q_i on a spiral of tau turns in screen space, sample i at distance
// h_i = alpha_i h_r from C (alpha_i = (i + 0.5) / s, h_r = the world radius r projected at
// z_C) and angle 2 pi alpha_i tau + phi_C (phi_C: a per-pixel hash), read at pyramid level
// m_i = clamp(floor(log2 h_i) - 3, 0, levels - 1) so that far samples stay in cache (SAO
// section 2.2). sigma = intensity, k = contrast, beta = bias (scaled by z_C), H = Heaviside.
// Pixels where nothing was drawn get A = 1.
#include "ao_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_AO_INPUT) uniform sampler2D cszPyramid;
layout(binding = VEIL_IMG_OUTPUT, r16f) uniform writeonly image2D aoRaw;

uniform float aoRadius;    // r, view-space units
uniform float aoIntensity; // sigma
uniform float aoContrast;  // k
uniform float aoBias;      // beta
uniform float aoEpsilon;   // epsilon
uniform int aoSamples;     // s
uniform int aoTurns;       // tau
uniform int aoLevels;      // pyramid levels (1 = no pyramid)

const float kTwoPi = 6.28318530717958647692;

// The sample's camera-space point: z from pyramid level `level` at q's texel, placed at the
// pixel that texel's z came from (the rotated-grid choice of csz_downsample.comp followed back
// to level 0), so that a far sample lies on the surface, not off it by the depth slope across
// its 2^m block (SAO reconstructs at q itself; on a grazing floor that reads as occlusion).
vec3 aoPositionAt(ivec2 q, int level) {
    ivec2 t = clamp(q >> level, ivec2(0), textureSize(cszPyramid, level) - 1);
    float z = texelFetch(cszPyramid, t, level).r;
    for (int k = level; k > 0; --k)
        t = min(t * 2 + ivec2((t.y & 1) ^ 1, (t.x & 1) ^ 1), textureSize(cszPyramid, k - 1) - 1);
    return aoViewPosition(vec2(t) + 0.5, z);
}

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(cszPyramid, 0);
    if (any(greaterThanEqual(c, size))) return;
    float zC = texelFetch(cszPyramid, c, 0).r;
    if (zC >= camera.viewport.w * 0.999) { // the far plane: nothing drawn
        imageStore(aoRaw, c, vec4(1.0));
        return;
    }
    vec3 P = aoViewPosition(vec2(c) + 0.5, zC);
    // Normal from the neighbour on each axis whose depth is closer (no normal across a
    // silhouette); oriented toward the camera.
    vec3 px = aoPositionAt(min(c + ivec2(1, 0), size - 1), 0) - P;
    vec3 nx = P - aoPositionAt(max(c - ivec2(1, 0), ivec2(0)), 0);
    vec3 py = aoPositionAt(min(c + ivec2(0, 1), size - 1), 0) - P;
    vec3 ny = P - aoPositionAt(max(c - ivec2(0, 1), ivec2(0)), 0);
    vec3 dx = abs(px.z) < abs(nx.z) ? px : nx;
    vec3 dy = abs(py.z) < abs(ny.z) ? py : ny;
    vec3 n = normalize(cross(dx, dy));
    if (dot(n, P) > 0.0) n = -n;

    float hr = aoRadius * aoPixelsPerUnit(zC);
    float phi = kTwoPi * float(aoHash(uvec2(c)) & 0xffffu) / 65536.0;
    float r2 = aoRadius * aoRadius;
    float sum = 0.0;
    for (int i = 0; i < aoSamples; ++i) {
        float a = (float(i) + 0.5) / float(aoSamples);
        float theta = kTwoPi * a * float(aoTurns) + phi;
        float h = a * hr;
        ivec2 q = c + ivec2(round(h * vec2(cos(theta), sin(theta))));
        q = clamp(q, ivec2(0), size - 1);
        int level = clamp(findMSB(int(h)) - 3, 0, aoLevels - 1);
        vec3 v = aoPositionAt(q, level) - P;
        float vv = dot(v, v);
        if (vv < r2) sum += max(0.0, dot(v, n) - aoBias * zC) / (vv + aoEpsilon);
    }
    float A = max(0.0, 1.0 - 2.0 * aoIntensity / float(aoSamples) * sum);
    imageStore(aoRaw, c, vec4(pow(A, aoContrast)));
}
