#include "bindings.h"
layout(std140, binding = VEIL_UBO_CAMERA) uniform CameraBlock {
    mat4 view;
    mat4 projection;
    mat4 viewProjection;
    vec4 cameraPosition; // xyz world position
    vec4 cameraRight;    // xyz world right vector (billboards)
    vec4 cameraUp;       // xyz world up vector (billboards)
    vec4 cameraForward;  // xyz world view direction, w = 1 for orthographic
    vec4 viewport;       // width, height, near, far
} camera;

// Unit vector from P toward the eye (parallel rays for an orthographic camera).
vec3 viewVector(vec3 P) {
    return camera.cameraForward.w > 0.5 ? -camera.cameraForward.xyz
                                        : normalize(camera.cameraPosition.xyz - P);
}
