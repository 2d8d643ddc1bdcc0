#version 450 core
// Zeroes the three moment arrays (every layer) before the transparent casters are blended in.
// A compute pass instead of glClearNamedFramebufferfv on the framebuffer: on the H200 the
// framebuffer clear of three RGBA32F 2048^2 targets went through the few graphics units and
// took ~4.2 ms of fog.json's frame (bench/RESULTS.md, "fog-frame"); stores from compute run at
// memory bandwidth. The values are the same zeros.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
uniform ivec2 rows; // texel rows [rows.x, rows.y) of this dispatch (moment.cpp, banded runs)
layout(binding = 1, rgba32f) uniform writeonly image2DArray absorbanceImage;
layout(binding = 2, rgba32f) uniform writeonly image2DArray momentImage;
layout(binding = 3, rgba32f) uniform writeonly image2DArray mediaMomentImage;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID) + ivec3(0, rows.x, 0);
    if (c.x >= imageSize(absorbanceImage).x || c.y >= rows.y) return;
    imageStore(absorbanceImage, c, vec4(0.0));
    imageStore(momentImage, c, vec4(0.0));
    imageStore(mediaMomentImage, c, vec4(0.0));
}
