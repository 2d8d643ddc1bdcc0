// Lookups in the opaque casters' depth array (src/shadows/common/depth_maps.h), shared by
// every shadow technique: each of them also needs the opaque map. params[0].x = bias (world
// units), params[0].y = PCF radius.
#include "../../common/lights.glsl"
#include "views.glsl"

layout(binding = VEIL_TEX_SHADOW_MAP) uniform sampler2DArrayShadow shadowDepthArray;

// The light view that sees P, its map uv and normalized depth; false = P is not shadowed.
bool shadowLocate(int light, vec3 P, out int view, out vec2 uv, out float depth) {
    view = shadowViewOf(light, P, lighting.lights[light].positionType.xyz);
    return shadowViewCoordinates(view, P, uv, depth);
}

// Surfaces: slope-scaled receiver bias (grows where the light grazes the surface), PCF.
float opaqueVisibility(int light, vec3 P, vec3 N, vec3 L) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(light, P, v, uv, z)) return 1.0;
    float NdotL = saturate(dot(N, L));
    float bias = shadows.params[0].x * (1.0 + 4.0 * (1.0 - NdotL)) / shadowViewDepthScale(v);
    int r = int(shadows.params[0].y);
    float texel = shadows.mapSize.y;
    float sum = 0.0;
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x)
            sum += texture(shadowDepthArray, vec4(uv + vec2(x, y) * texel, float(v), z - bias));
    float n = float(2 * r + 1);
    return sum / (n * n);
}

// Volume samples: one hardware-filtered tap (bilinear 2x2 comparison); the fog marcher takes
// many samples per pixel, so per-sample PCF kernels are not worth their cost.
float opaqueVisibilityFast(int light, vec3 P) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(light, P, v, uv, z)) return 1.0;
    return texture(shadowDepthArray,
                   vec4(uv, float(v), z - shadows.params[0].x / shadowViewDepthScale(v)));
}
