#version 450 core
// Shadow volumes (src/shadows/volume): every opaque object's vertices into world space, once
// per frame, for the depth pre-pass (volume.vert) and the silhouettes (silhouette.comp). Both
// read these very values, so a lit face and its own front cap are the same vec4 through the
// same vertex shader: equal depths with no bias.
#include "../../common/bindings.h"

layout(local_size_x = 256) in;
struct SourceVertex {
    vec3 position; // the mesh's (object space)
    uint object;   // into models[]
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_SOURCE) readonly buffer Source {
    SourceVertex source[];
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_MODELS) readonly buffer Models {
    mat4 models[];
};
layout(std430, binding = VEIL_SSBO_SHADOW_VOLUME_WORLD) writeonly buffer World {
    vec4 world[]; // w = 1
};
uniform int vertexCount;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= vertexCount) return;
    SourceVertex s = source[i];
    world[i] = vec4((models[s.object] * vec4(s.position, 1.0)).xyz, 1.0);
}
