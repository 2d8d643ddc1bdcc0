// Screen-space ambient obscurance (src/frame/ambient_occlusion.h): camera-space geometry from
// the opaque depth. z is the positive view distance; positions are view space (-z forward).
#include "../../common/bindings.h"
#include "../../common/camera.glsl"

// View distance of window depth d (inverts the projection's z row: perspective and
// orthographic alike).
float aoViewDistance(float d) {
    mat4 P = camera.projection;
    float ndc = 2.0 * d - 1.0;
    return -(P[3][2] - ndc * P[3][3]) / (ndc * P[2][3] - P[2][2]);
}

// View-space position of the point at view distance z seen through pixel position p (pixel
// units, centre at +0.5): solves ndc.xy = (P v)_xy / (P v)_w for v = (x, y, -z).
vec3 aoViewPosition(vec2 p, float z) {
    mat4 P = camera.projection;
    vec2 ndc = 2.0 * p / camera.viewport.xy - 1.0;
    float w = -P[2][3] * z + P[3][3];
    float x = (ndc.x * w + P[2][0] * z - P[3][0]) / P[0][0];
    float y = (ndc.y * w + P[2][1] * z - P[3][1]) / P[1][1];
    return vec3(x, y, -z);
}

// Pixels per view-space unit at view distance z (vertical), for the screen-space radius.
float aoPixelsPerUnit(float z) {
    mat4 P = camera.projection;
    return 0.5 * camera.viewport.y * P[1][1] / (-P[2][3] * z + P[3][3]);
}

// Integer hash of a pixel (the per-pixel rotation of the sample spiral): exact in any
// arithmetic, so the CPU reference reproduces it bit for bit.
uint aoHash(uvec2 p) {
    uint h = p.x * 0x8da6b343u ^ p.y * 0xd8163841u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    return h;
}
