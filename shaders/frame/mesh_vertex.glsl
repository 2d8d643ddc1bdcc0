// The vertex transform of every mesh draw (frame/mesh.vert) and of the compute rasterizer's
// setup (frame/raster_setup.glsl): world position and normal (billboards expanded along
// `right` and `up`), view depth and clip position.
#include "../common/camera.glsl"

struct MeshVertex {
    vec3 world;
    vec3 normal;
    float viewDepth;
};

MeshVertex meshVertex(vec3 position, vec3 normalIn, vec2 uv, float size, mat4 model,
                      mat3 normalMatrix, bool billboard, vec3 right, vec3 up, bool faceLight) {
    MeshVertex v;
    v.world = (model * vec4(position, 1.0)).xyz;
    v.normal = normalize(normalMatrix * normalIn);
    if (billboard) {
        v.world += (right * uv.x + up * uv.y) * size;
        v.normal = faceLight ? normalize(cross(right, up)) : viewVector(v.world);
    }
    v.viewDepth = -(camera.view * vec4(v.world, 1.0)).z;
    return v;
}
