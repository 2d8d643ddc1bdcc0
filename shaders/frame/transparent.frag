#version 450 core
// Transparent surfaces from the hardware rasterizer: shaded (frame/transparent_surface.glsl)
// and handed to the active OIT technique's oitEmit().
#include "transparent_surface.glsl"

void main() {
    OitFragment f;
    if (!transparentFragment(f)) discard;
    oitEmit(f);
}
