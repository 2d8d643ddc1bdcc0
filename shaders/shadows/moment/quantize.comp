#version 450 core
// 16-bit storage of the filtered moment maps (docs/oit.md#moment-constants; [Munstermann18 sec. 6] discarded
// 16-bit shadow moments because linear filtering of the normalized moments b_k / b0 breaks
// where b0 vanishes, and notes that "specialized compute shaders should make it practical"):
// the float32 maps are filtered first, then this pass stores the b0 (surfaces per channel,
// media) as half floats and both sets of normalized moments through the 4-moment quantization
// transform as UNORM16. Receivers fetch the four texels of a bilinear footprint, undo the normalization
// (multiply by b0) and only then interpolate (visibility.glsl), so no normalized value is
// filtered.
#include "../../common/bindings.h"
#include "../../common/moment_quantize.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray absorbance32;
layout(binding = VEIL_TEX_SHADOW2) uniform sampler2DArray moments32;
layout(binding = VEIL_TEX_SHADOW3) uniform sampler2DArray mediaMoments32;
uniform ivec2 rows; // texel rows [rows.x, rows.y) of this dispatch (moment.cpp, banded runs)
layout(binding = 1, rgba16f) uniform writeonly image2DArray absorbance16;
layout(binding = 2, rgba16) uniform writeonly image2DArray moments16;
layout(binding = 3, rgba16) uniform writeonly image2DArray mediaMoments16;

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID) + ivec3(0, rows.x, 0);
    ivec3 size = imageSize(absorbance16);
    if (c.x >= size.x || c.y >= rows.y || c.z >= size.z) return;
    vec4 b0 = texelFetch(absorbance32, c, 0);
    float surfaces = (b0.r + b0.g + b0.b) / 3.0;
    // Empty texels store the quantized normalized moments of a point at z = 0 (any valid
    // point works: b0 = 0 makes them irrelevant).
    vec4 n = surfaces > 0.0 ? texelFetch(moments32, c, 0) / surfaces : vec4(0.0);
    vec4 nm = b0.a > 0.0 ? texelFetch(mediaMoments32, c, 0) / b0.a : vec4(0.0);
    imageStore(absorbance16, c, b0);
    imageStore(moments16, c, clamp(momentQuantize4(n), 0.0, 1.0));
    imageStore(mediaMoments16, c, clamp(momentQuantize4(nm), 0.0, 1.0));
}
