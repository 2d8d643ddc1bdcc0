#version 450 core
// Shadow volumes (src/shadows/volume): object -> world positions for volume.geom, with the
// vertex index, so that the geometry stage can order every triangle's vertices the same way
// wherever it is read (its own invocation or a neighbour's adjacency).
#include "../../common/bindings.h"

layout(location = VEIL_ATTR_POSITION) in vec3 inPosition;
uniform mat4 model;

out vec3 gWorld;
flat out int gIndex;

void main() {
    gWorld = (model * vec4(inPosition, 1.0)).xyz;
    gIndex = gl_VertexID;
    gl_Position = vec4(gWorld, 1.0);
}
