#version 450 core
// Test probe (tests/gl/shadow_bands_test.cpp): every sample of every texel and layer of a
// multisample depth array into a buffer, so that two such textures can be compared bit for bit
// (glGetTextureImage does not read multisample textures).
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = 0) uniform sampler2DMSArray source;
layout(std430, binding = 0) writeonly buffer Out { float values[]; };

uniform int samples;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec3 size = textureSize(source);
    if (any(greaterThanEqual(p, size))) return;
    uint base = ((uint(p.z) * uint(size.y) + uint(p.y)) * uint(size.x) + uint(p.x)) * uint(samples);
    for (int s = 0; s < samples; ++s)
        values[base + uint(s)] = texelFetch(source, p, s).r;
}
