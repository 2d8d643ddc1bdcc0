#version 450 core
// Transparent surfaces from the hardware rasterizer: shaded (frame/transparent_surface.glsl)
// and handed to the active OIT technique's oitEmit(). The receiver-plane shadow slope comes
// from the fragment's screen-space derivatives (shadows/common/receiver_derivatives.glsl),
// taken first, in uniform control flow.
#define VEIL_RECEIVER_DERIVATIVES 1
#include "transparent_surface.glsl"

void main() {
    shadowReceiverDerivatives(vWorldPos);
    OitFragment f;
    if (!transparentFragment(f)) discard;
    oitEmit(f);
}
