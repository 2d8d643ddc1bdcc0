#version 450 core
// TEMPLATE stage (src/frame/stages/_template/): scales the HDR radiance of the pass's region
// by `gain`, in place.
#include "../../common/bindings.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = VEIL_IMG_OUTPUT, rgba16f) uniform image2D hdrImage;

uniform float gain;
// The pixels of this dispatch, [x0, y0) .. [x1, y1): the whole frame or a refinement tile.
uniform ivec4 region;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy) + region.xy;
    ivec2 size = imageSize(hdrImage);
    if (p.x >= min(size.x, region.z) || p.y >= min(size.y, region.w)) return;
    vec4 c = imageLoad(hdrImage, p);
    imageStore(hdrImage, p, vec4(c.rgb * gain, c.a));
}
