#version 450 core
// [Eisemann06 sec. 3.2] "clamping": the receivers the camera sees (its depth pre-pass) voxelized into
// each light's slice map, one bit per (column, slice). A receiver outside a light's grid sets
// the slot's `unbounded` flag: that light is then neither clamped nor receiver-culled.
#include "grid.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_TEX_SHADOW2) uniform sampler2D sceneDepth;
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_RECEIVERS) buffer Receivers {
    uint unbounded[VEIL_MAX_LIGHTS];
    uint receiverWords[];
};
uniform mat4 invViewProjection;
uniform ivec2 screenSize;
uniform int slotCount;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, screenSize))) return;
    float z = texelFetch(sceneDepth, p, 0).r;
    if (z >= 1.0) return; // background: no receiver
    vec4 ndc = vec4((vec2(p) + 0.5) / vec2(screenSize) * 2.0 - 1.0, z * 2.0 - 1.0, 1.0);
    vec4 w = invViewProjection * ndc;
    vec3 P = w.xyz / w.w;
    for (int slot = 0; slot < slotCount; ++slot) {
        int v = uSlotView[slot];
        if (v < 0) continue;
        // A spot light's receivers outside its view are outside its cone (unlit): skipped.
        // Anything else outside the grid (none, with views fitted to the scene) is unbounded.
        bool ortho = shadows.views[v].depthRange.w > 0.5;
        vec4 t = shadows.views[v].worldToTexture * vec4(P, 1.0);
        vec2 uv = t.xy / t.w;
        // (1e-3 of slack: views are fitted to the scene's bounds, whose faces are receivers)
        if (t.w <= 0.0 || any(lessThan(uv, vec2(-1e-3))) || any(greaterThan(uv, vec2(1.001)))) {
            if (ortho) unbounded[slot] = 1u;
            continue;
        }
        float d = shadowViewDepth(v, P);
        if (d < -1e-3 || d > 1.001) {
            unbounded[slot] = 1u;
            continue;
        }
        ivec2 c = clamp(ivec2(uv * float(uGrid)), ivec2(0), ivec2(uGrid - 1));
        int s = clamp(int(d * float(uSlices)), 0, uSlices - 1);
        // Most pixels of a column land in a slice that is already set: read before the atomic.
        uint word = uint(gridColumn(slot, c) * gridWords() + s / 32), bit = 1u << uint(s % 32);
        if ((receiverWords[word] & bit) == 0u) atomicOr(receiverWords[word], bit);
    }
}
