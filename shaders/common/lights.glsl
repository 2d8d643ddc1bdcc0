// Scene lights: the uniform block the frame fills (src/frame/frame_uniforms.h) and the
// unshadowed radiance arriving from each. Visibility toward a light comes from the active
// shadow technique through "veil:light_visibility" (shaders/frame/shading.glsl).
#include "bindings.h"
#include "brdf.glsl"

struct Light {
    vec4 positionType;    // xyz position, w = VEIL_LIGHT_*
    vec4 directionShadow; // xyz direction light travels, w = 1 if it casts shadows
    vec4 radiance;        // rgb = color * intensity
    vec4 cone;            // cos(inner), cos(outer)
};

layout(std140, binding = VEIL_UBO_LIGHTS) uniform LightsBlock {
    Light lights[VEIL_MAX_LIGHTS];
    ivec4 lightCount;     // x = number of lights
    vec4 ambient;         // rgb ambient factor (times diffuse albedo)
} lighting;

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
