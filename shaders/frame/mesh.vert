#version 450 core
// Vertex stage shared by the opaque, transparent and shadow passes.
#include "mesh_vertex.glsl"

layout(location = VEIL_ATTR_POSITION) in vec3 inPosition;
layout(location = VEIL_ATTR_NORMAL) in vec3 inNormal;
layout(location = VEIL_ATTR_UV) in vec2 inUv;
layout(location = VEIL_ATTR_SIZE) in float inSize;

uniform mat4 model;
uniform mat3 normalMatrix;
uniform bool billboard;      // quad particles: expand toward the camera
uniform mat4 viewProjection; // overrides the camera's (shadow passes) when useOverride
uniform bool useOverride;
uniform vec3 overrideRight;  // billboard axes when useOverride: particles face the light
uniform vec3 overrideUp;

out vec3 vWorldPos;
out vec3 vNormal;
out vec2 vUv;
out float vViewDepth;

void main() {
    vec3 right = useOverride ? overrideRight : camera.cameraRight.xyz;
    vec3 up = useOverride ? overrideUp : camera.cameraUp.xyz;
    MeshVertex v = meshVertex(inPosition, inNormal, inUv, inSize, model, normalMatrix, billboard,
                              right, up, useOverride);
    vWorldPos = v.world;
    vNormal = v.normal;
    vUv = inUv;
    vViewDepth = v.viewDepth;
    gl_Position = (useOverride ? viewProjection : camera.viewProjection) * vec4(v.world, 1.0);
}
