#version 450 core
// FogDepthMap (src/shadows/common/fog_depth.h): per light view, the optical depth of the grid
// density volumes along every fog column of the view, accumulated slice by slice (uniform
// slices of the view's [near, far] range). Texel (x, y, view * (slices + 1) + k) holds the
// optical depth from the near plane to slice boundary k = 0 .. slices (boundary 0 = 0), so a
// receiver at slice coordinate fs reads it with linear filtering at fs (fog_depth.glsl) and
// gets exp(-tau). Each slice integrates `uSubsteps` midpoint samples of the density along the
// column's centre ray.
#include "views.glsl"
#include "../../volume/volume_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_IMG_VOLUME_LIGHT, r32f) uniform writeonly image3D uTau;

uniform int shadowView;
uniform int uSlices;
uniform int uSubsteps;
uniform int uColumns;
uniform ivec2 rows; // column rows [rows.x, rows.y) of this dispatch (bands, the .cpp)
uniform mat4 uClipToWorld; // inverse of the view's viewProjection

float densityAt(vec3 w) {
    float sigma = 0.0;
    for (int i = 0; i < volumeCount; ++i) {
        bool empty;
        vec3 p = (volumes[i].worldToIndex * vec4(w, 1.0)).xyz;
        sigma += volumes[i].densityScale * sampleVolumeIndex(i, p, empty);
    }
    return sigma;
}

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
    vec3 perT = (B - A) / (tB - tA); // world per unit of normalized depth
    float dt = 1.0 / float(uSlices), h = dt / float(uSubsteps), len = length(perT) * h;
    float tau = 0.0;
    int z0 = shadowView * (uSlices + 1);
    for (int k = 0; k < uSlices; ++k) {
        imageStore(uTau, ivec3(c, z0 + k), vec4(tau));
        for (int j = 0; j < uSubsteps; ++j) {
            float t = (float(k) + (float(j) + 0.5) / float(uSubsteps)) * dt;
            tau += densityAt(A + perT * (t - tA)) * len;
        }
    }
    imageStore(uTau, ivec3(c, z0 + uSlices), vec4(tau));
}
