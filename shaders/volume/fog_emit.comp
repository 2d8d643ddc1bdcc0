#version 450 core
// Hands the marched fog to the active OIT technique from compute, one invocation
// per pixel: the technique's own oitEmit() (its emit file included with OIT_COMPUTE defined,
// writing its targets as images through OIT_WRITE, shaders/oit/fragment.glsl). The depth test
// of the accumulation passes (GL_LESS against the opaque depth) is done here, at the fog's
// representative depth, as the fragment emitter's gl_FragDepth would be tested.
#include "../common/camera.glsl"

#include "veil:oit_emit"

#include "fog_contribution.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The pixels [x0, y0) .. [x1, y1) of this dispatch (the whole frame, or a tile of the viewer's
// refinement: frame::Renderer::refineStep).
uniform ivec4 emitRegion;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy) + emitRegion.xy;
    if (any(greaterThanEqual(p, min(emitRegion.zw, textureSize(opaqueDepth, 0))))) return;
    vec4 L, T;
    if (!fogContribution(p, L, T)) return;
    float depth = fogWindowDepth(L.a);
    if (!(depth < texelFetch(opaqueDepth, p, 0).r)) return;
    oitPixel = p;
    oitWindowDepth = depth;
    oitEmit(oitFragment(L.rgb, 1.0, T.rgb, L.a)); // no surface, no particle
}
