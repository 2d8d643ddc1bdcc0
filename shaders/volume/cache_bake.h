// Binding slots of the scattered-light cache's GPU bake (shaders/volume/cache_bake.comp,
// src/fog/scattered_light_bake.cpp; read by both: keep it to #defines). The bake runs between
// the frame's passes, so it may reuse units the passes bind for themselves.
#ifndef VEIL_CACHE_BAKE_H
#define VEIL_CACHE_BAKE_H

#define VEIL_SSBO_CACHE_BAKE 7    // per texel: sum of L (rgb) and of Y^2 (a); sum of Y (-d) (xyz)
#define VEIL_SSBO_CACHE_TEXELS 8   // uint: the texels of a surface pass (texelList != 0)
#define VEIL_IMG_CACHE_MEAN 6     // rgba32f: mean radiance (rgb), its luminance (a)
#define VEIL_IMG_CACHE_FLUX 7     // rgba32f: P1 flux G (xyz)
#define VEIL_CACHE_BAKE_GROUP 64  // invocations per work group (one texel each)
#define VEIL_CACHE_MAX_LIGHTS 8   // as VEIL_MAX_LIGHTS
#define VEIL_TEX_CACHE_MAJORANT 24 // r32f: majorant per cell (VEIL_TEX_VOLUME_LIGHT's unit)

#endif
