#version 450 core
// Self-shadowing of density volumes: for each texel of a light-space transmittance volume
// (covering one volume's world bounds) march toward the light through every volume and store
// exp(-optical depth). The fog marcher multiplies in-scattered light by it.
#include "volume_common.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = VEIL_IMG_VOLUME_LIGHT, r32f) uniform writeonly image3D lightTransmittance;

uniform mat4 lightToWorld; // [0,1]^3 of the target texture -> world
uniform vec4 lightPositionType; // xyz position (or travel direction for directional), w = type
uniform int steps;
uniform float maxDistance; // world distance that covers all volumes
uniform ivec2 zRange;      // the z slices [x, y) of this dispatch (from x; the whole depth in one piece)

void main() {
    ivec3 size = imageSize(lightTransmittance);
    ivec3 c = ivec3(gl_GlobalInvocationID) + ivec3(0, 0, zRange.x);
    if (any(greaterThanEqual(c, size)) || c.z >= zRange.y) return;
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
    // Midpoint rule with `steps` samples over [0, distance]. Samples outside every volume's box
    // and in empty leaves are zero, so only the steps inside the union of the boxes are taken
    // and empty leaves are jumped over: the same sum as visiting every step, at a fraction of
    // the cost (this pass was most of the lit fog's time on llvmpipe).
    float tIn = 1e30, tOut = -1e30;
    for (int i = 0; i < VEIL_VOLUME_SLOTS; ++i)
        if (i < volumeCount) {
            vec2 iv = volumeBoxInterval(i, P, L);
            tIn = min(tIn, iv.x);
            tOut = max(tOut, iv.y);
        }
    // One step of margin on each side: the box test and the sampler's bounds test round apart.
    int first = max(int(floor(tIn / dt - 0.5)) - 1, 0);
    int last = min(int(ceil(tOut / dt - 0.5)) + 1, steps - 1);
    float tau = 0.0;
    for (int s = first; s <= last; ++s) {
        float t = (float(s) + 0.5) * dt;
        bool empty;
        tau += volumeExtinctionOrEmpty(P + L * t, empty) * dt;
        if (empty) s = max(s, firstStepPast(t, volumesLeafExit(P + L * t, L), 0.0, dt, 0.5) - 1);
    }
    imageStore(lightTransmittance, c, vec4(exp(-tau)));
}
