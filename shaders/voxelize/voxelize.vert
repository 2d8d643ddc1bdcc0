#version 450
// Grid-camera vertex stage of the raster voxelizers ([Eisemann06 sec. 2]: the grid is a camera).
layout(location = 0) in vec3 aPosition; // world space
uniform mat4 uViewProj;
out vec3 vWorld;
void main() {
    vWorld = aPosition;
    gl_Position = uViewProj * vec4(aPosition, 1.0);
}
