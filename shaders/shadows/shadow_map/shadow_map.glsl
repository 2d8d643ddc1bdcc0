// Williams (1978) shadow map of opaque casters for the light that owns it: linear depth along
// the light axis (shaders/frame/shadow.frag), PCF over (2r+1)^2 taps for surfaces, one
// hardware-filtered tap for volume samples.
#include "../../common/lights.glsl"

layout(binding = VEIL_TEX_SHADOW_MAP) uniform sampler2DShadow shadowMap;

// Normalized linear depth of P along the shadow-casting light's axis.
float shadowLinearDepth(vec3 P) {
    float d = -(lighting.shadowView * vec4(P, 1.0)).z;
    return (d - lighting.shadowDepthRange.x) /
           (lighting.shadowDepthRange.y - lighting.shadowDepthRange.x);
}

// Shadow-map coordinates of P: texture uv and normalized linear depth. False where P is
// outside the map (lit).
bool shadowCoordinates(vec3 P, out vec2 uv, out float z) {
    if (lighting.shadowParams.w < 0.5) return false;
    vec4 s = lighting.shadowMatrix * vec4(P, 1.0);
    if (s.w <= 0.0) return false;
    uv = s.xy / s.w;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return false;
    // The map stores linear depth along the light axis (uniform precision; the bias is in
    // world units), see shaders/frame/shadow.frag.
    z = shadowLinearDepth(P);
    return z <= 1.0;
}

float shadowVisibility(vec3 P, vec3 N, vec3 L) {
    vec2 uv;
    float z;
    if (!shadowCoordinates(P, uv, z)) return 1.0;
    float NdotL = saturate(dot(N, L));
    // Slope-scaled receiver bias: grows where the light grazes the surface.
    float range = lighting.shadowDepthRange.y - lighting.shadowDepthRange.x;
    float bias = lighting.shadowParams.x * (1.0 + 4.0 * (1.0 - NdotL)) / range;
    int r = int(lighting.shadowParams.y);
    float texel = lighting.shadowParams.z;
    float sum = 0.0;
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x)
            sum += texture(shadowMap, vec3(uv + vec2(x, y) * texel, z - bias));
    float n = float(2 * r + 1);
    return sum / (n * n);
}

// One hardware-filtered tap (bilinear 2x2 comparison), for volume samples: the fog marcher
// takes many samples per pixel, so per-sample PCF kernels are not worth their cost.
float shadowVisibilityFast(vec3 P) {
    vec2 uv;
    float z;
    if (!shadowCoordinates(P, uv, z)) return 1.0;
    float range = lighting.shadowDepthRange.y - lighting.shadowDepthRange.x;
    return texture(shadowMap, vec3(uv, z - lighting.shadowParams.x / range));
}
