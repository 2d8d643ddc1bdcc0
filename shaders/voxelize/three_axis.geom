#version 450
// Dominant-axis selection (three-axis voxelization): a triangle is rasterized only in the
// view along the world axis of its largest normal component, where its projected area is
// largest, so plain rasterization leaves a 6-separating (thin, hole-free) voxel shell.
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 vWorld[];
uniform int uAxis;
void main() {
    vec3 n = abs(cross(vWorld[1] - vWorld[0], vWorld[2] - vWorld[0]));
    int dominant = n.x >= n.y && n.x >= n.z ? 0 : (n.y >= n.z ? 1 : 2);
    if (dominant != uAxis) return;
    for (int i = 0; i < 3; ++i) {
        gl_Position = gl_in[i].gl_Position;
        EmitVertex();
    }
    EndPrimitive();
}
