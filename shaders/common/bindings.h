// Binding slots shared by C++ and GLSL (read by both: keep it to #defines).
#ifndef VEIL_BINDINGS_H
#define VEIL_BINDINGS_H

#define VEIL_UBO_CAMERA 0
#define VEIL_UBO_LIGHTS 1

#define VEIL_TEX_SHADOW_MAP 0
#define VEIL_TEX_HDR 1
#define VEIL_TEX_DEPTH 2
#define VEIL_TEX_OIT0 4

#define VEIL_IMG_OUTPUT 0

#define VEIL_MAX_LIGHTS 8

// Voxelization (src/voxelize, shaders/voxelize): slice-map words, per-column local-slicing
// ranges (near, far pairs), triangle soup, per-axis maps of three-axis voxelization.
#define VEIL_SSBO_VOX_WORDS 8
#define VEIL_SSBO_VOX_RANGE 9
#define VEIL_SSBO_VOX_TRIS 10
#define VEIL_SSBO_VOX_AXIS0 11
#define VEIL_TEX_VOX0 16
#define VEIL_TEX_VOX_RANGE 24

#define VEIL_ATTR_POSITION 0
#define VEIL_ATTR_NORMAL 1
#define VEIL_ATTR_UV 2
#define VEIL_ATTR_SIZE 3

#define VEIL_LIGHT_DIRECTIONAL 0
#define VEIL_LIGHT_SPOT 1
#define VEIL_LIGHT_POINT 2

#endif
