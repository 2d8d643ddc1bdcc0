// Scene lights and the opaque shadow map (Williams 1978, PCF over (2r+1)^2 taps).
#include "bindings.h"
#include "brdf.glsl"

struct Light {
    vec4 positionType;    // xyz position, w = VEIL_LIGHT_*
    vec4 directionShadow; // xyz direction light travels, w = 1 if it owns the shadow map
    vec4 radiance;        // rgb = color * intensity
    vec4 cone;            // cos(inner), cos(outer)
};

layout(std140, binding = VEIL_UBO_LIGHTS) uniform LightsBlock {
    Light lights[VEIL_MAX_LIGHTS];
    ivec4 lightCount;     // x = number of lights
    mat4 shadowMatrix;    // world -> shadow map texture coordinates (projective)
    mat4 shadowView;      // world -> light view space (depth = -z)
    vec4 ambient;         // rgb ambient factor (times diffuse albedo)
    vec4 shadowParams;    // x = bias (world units), y = PCF radius, z = 1 / map size, w = has map
    vec4 shadowDepthRange; // x = near, y = far of the stored linear depth
} lighting;

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

// Radiance arriving at P from light i (unshadowed) and the direction toward the light.
vec3 incidentRadiance(int i, vec3 P, out vec3 L) {
    Light light = lighting.lights[i];
    int type = int(light.positionType.w);
    if (type == VEIL_LIGHT_DIRECTIONAL) {
        L = -light.directionShadow.xyz;
        return light.radiance.rgb;
    }
    vec3 d = light.positionType.xyz - P;
    float dist2 = max(dot(d, d), 1e-8);
    L = d * inversesqrt(dist2);
    vec3 e = light.radiance.rgb / dist2;
    if (type == VEIL_LIGHT_SPOT) {
        float cosAngle = dot(-L, light.directionShadow.xyz);
        e *= smoothstep(light.cone.y, light.cone.x, cosAngle);
    }
    return e;
}

// Reflected radiance toward V: all lights with shadows plus the ambient term.
vec3 shadeSurface(SurfaceMaterial m, vec3 P, vec3 N, vec3 V, float diffuseWeight) {
    vec3 result = m.emission + lighting.ambient.rgb * m.baseColor * (1.0 - m.metalness) *
                                   diffuseWeight;
    for (int i = 0; i < lighting.lightCount.x; ++i) {
        vec3 L;
        vec3 e = incidentRadiance(i, P, L);
        if (dot(N, L) <= 0.0) continue;
        if (lighting.lights[i].directionShadow.w > 0.5) e *= shadowVisibility(P, N, L);
        result += e * evaluateBrdfCos(m, N, V, L, diffuseWeight);
    }
    return result;
}
