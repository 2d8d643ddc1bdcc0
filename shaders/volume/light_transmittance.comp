#version 450 core
// Self-shadowing of density volumes: for each texel of a light-space transmittance volume
// (covering one volume's world bounds) march toward the light through every volume and store
// exp(-optical depth). The fog marcher multiplies in-scattered light by it.
#include "volume_common.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = VEIL_IMG_VOLUME_LIGHT, r16f) uniform writeonly image3D lightTransmittance;

uniform mat4 lightToWorld; // [0,1]^3 of the target texture -> world
uniform vec4 lightPositionType; // xyz position (or travel direction for directional), w = type
uniform int steps;
uniform float maxDistance; // world distance that covers all volumes

void main() {
    ivec3 size = imageSize(lightTransmittance);
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, size))) return;
    vec3 uvw = (vec3(c) + 0.5) / vec3(size);
    vec3 P = (lightToWorld * vec4(uvw, 1.0)).xyz;
    vec3 L;
    float distance = maxDistance;
    if (int(lightPositionType.w) == VEIL_LIGHT_DIRECTIONAL) {
        L = -normalize(lightPositionType.xyz);
    } else {
        vec3 d = lightPositionType.xyz - P;
        distance = min(distance, length(d));
        L = d / max(length(d), 1e-6);
    }
    float dt = distance / float(steps);
    float tau = 0.0;
    for (int s = 0; s < steps; ++s) tau += volumeExtinction(P + L * ((float(s) + 0.5) * dt)) * dt;
    imageStore(lightTransmittance, c, vec4(exp(-tau)));
}
