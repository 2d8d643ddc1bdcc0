// The setup half of what the frame gives the compute rasterizer of the transparent pass
// (shaders/frame/compute_raster/setup.comp, one dispatch per object, the object's uniforms set
// and mesh buffers bound by frame::dispatchObjects): the mesh's buffers as SSBOs,
// surfaceTriangleIndex(), surfaceVertex() (frame/mesh.vert's transform: clip position and the
// SURFACE_ATTRIBUTES floats to interpolate) and surfaceRecord() (the object's material,
// SURFACE_RECORD_VEC4S vec4s). The fine half: frame/raster_surface.glsl.
#include "raster_layout.glsl"
#define SURFACE_UNIFORMS_ONLY 1
#include "material.glsl"
#include "mesh_vertex.glsl"

// Tightly packed attribute arrays of the mesh (frame::GpuMesh), read as floats.
layout(std430, binding = VEIL_SSBO_MESH_POSITIONS) readonly restrict buffer MeshPositions {
    float meshPositions[];
};
layout(std430, binding = VEIL_SSBO_MESH_NORMALS) readonly restrict buffer MeshNormals {
    float meshNormals[];
};
layout(std430, binding = VEIL_SSBO_MESH_UVS) readonly restrict buffer MeshUvs {
    float meshUvs[];
};
layout(std430, binding = VEIL_SSBO_MESH_SIZES) readonly restrict buffer MeshSizes {
    float meshSizes[];
};
layout(std430, binding = VEIL_SSBO_MESH_INDICES) readonly restrict buffer MeshIndices {
    uint meshIndices[];
};
uniform mat4 model;
uniform mat3 normalMatrix;

uint surfaceTriangleCount() { return uint(meshIndices.length()) / 3u; }
uint surfaceTriangleIndex(uint triangle, uint corner) { return meshIndices[3u * triangle + corner]; }

vec4 surfaceVertex(uint i, out float a[SURFACE_ATTRIBUTES]) {
    vec3 position = vec3(meshPositions[3u * i], meshPositions[3u * i + 1u], meshPositions[3u * i + 2u]);
    vec3 normal = vec3(meshNormals[3u * i], meshNormals[3u * i + 1u], meshNormals[3u * i + 2u]);
    vec2 uv = vec2(meshUvs[2u * i], meshUvs[2u * i + 1u]);
    MeshVertex v = meshVertex(position, normal, uv, meshSizes[i], model, normalMatrix, billboard,
                              camera.cameraRight.xyz, camera.cameraUp.xyz, false);
    a = float[SURFACE_ATTRIBUTES](v.world.x, v.world.y, v.world.z, v.normal.x, v.normal.y,
                                  v.normal.z, uv.x, uv.y, v.viewDepth);
    return camera.viewProjection * vec4(v.world, 1.0);
}

void surfaceRecord(out vec4 r[SURFACE_RECORD_VEC4S]) {
    r[0] = vec4(baseColor, roughness);
    r[1] = vec4(emission, metalness);
    r[2] = vec4(transmission, coverage);
    r[3] = vec4(attenuationColor, attenuationDistance);
    r[4] = vec4(collimation, ior, coverageEdge, 0.0);
    r[5] = vec4(billboard ? 1.0 : 0.0, binaryCoverage ? 1.0 : 0.0, 0.0, 0.0);
}
