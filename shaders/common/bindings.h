// Binding slots shared by C++ and GLSL (read by both: keep it to #defines).
#ifndef VEIL_BINDINGS_H
#define VEIL_BINDINGS_H

#define VEIL_UBO_CAMERA 0
#define VEIL_UBO_LIGHTS 1
#define VEIL_UBO_SHADOWS 2 // shadows/common/views.glsl (src/shadows/views.h)

// The shadow technique's textures, read by every receiver (src/shadows): the opaque casters'
// depth array (one layer per light view) and up to three technique-specific textures.
#define VEIL_TEX_SHADOW_MAP 0
#define VEIL_TEX_SHADOW1 28
#define VEIL_TEX_SHADOW2 29
#define VEIL_TEX_SHADOW3 30
// A shadow-casting light has one view (directional, spot) or six (point: cube faces); the
// views of all shadowed lights are the layers of the technique's texture arrays.
#define VEIL_MAX_SHADOW_VIEWS 24
// Shadow `reference`: per-texel fragment lists read by receivers (node pool, counter).
#define VEIL_SSBO_SHADOW_NODES 5
#define VEIL_SSBO_SHADOW_COUNTER 6
#define VEIL_TEX_HDR 1
#define VEIL_TEX_DEPTH 2
#define VEIL_TEX_AO 3 // the frame's ambient visibility (src/frame/ambient_occlusion.h), when on
#define VEIL_TEX_AO_INPUT 14 // the AO passes' own inputs (camera-space z pyramid, raw AO)
#define VEIL_TEX_OIT0 4

// OIT `phenomenological` ([McGuire16 Table 2] targets and the resolve's inputs).
#define VEIL_PHEN_TEX_DEPTH (VEIL_TEX_OIT0 + 0)
#define VEIL_PHEN_TEX_A (VEIL_TEX_OIT0 + 1)
#define VEIL_PHEN_TEX_BD (VEIL_TEX_OIT0 + 2)
#define VEIL_PHEN_TEX_DELTA (VEIL_TEX_OIT0 + 3)
#define VEIL_PHEN_TEX_BKG (VEIL_TEX_OIT0 + 4)
#define VEIL_PHEN_TEX_THICKNESS (VEIL_TEX_OIT0 + 5) // volumeRefraction: thickness per pixel
#define VEIL_PHEN_TEX_SLICES (VEIL_TEX_OIT0 + 0)    // thickness.comp: 8 slice-map words

#define VEIL_IMG_OUTPUT 0
#define VEIL_IMG_MOMENT0 1 // moment OIT 16-bit storage: images 1..3
#define VEIL_IMG_MOMENT1 2
#define VEIL_IMG_MOMENT2 3

// OIT `reference` (per-pixel linked lists) and `wboit` resolve targets.
#define VEIL_IMG_OIT_REF_HEADS 1
#define VEIL_IMG_OIT_REF_TARGET 2
#define VEIL_SSBO_OIT_REF_NODES 1
#define VEIL_SSBO_OIT_REF_COUNTERS 2
#define VEIL_IMG_OIT_WBOIT_TARGET 3
#define VEIL_IMG_OIT_REF_COUNT 3 // the reference resolve's nodes per pixel (r32f)
// Per-pixel emission from compute (shaders/oit/fragment.glsl OIT_TARGET): images 4..6, shared
// with the fog march's (bound again by every march); GL 4.5 guarantees units 0..7 only (NVIDIA
// has exactly 8: binding 8 fails to compile there).
#define VEIL_IMG_OIT_TARGET0 4

// Fog (src/fog): marcher outputs, and per-volume textures (VEIL_MAX_VOLUMES of each)
#define VEIL_TEX_FOG_RADIANCE 12
#define VEIL_TEX_FOG_TRANSMITTANCE 13
#define VEIL_TEX_VOLUME_DATA 16
#define VEIL_TEX_VOLUME_TABLE 20
#define VEIL_TEX_VOLUME_LIGHT 24
#define VEIL_TEX_VOLUME_EMISSION 32 // emission channel (temperature or emission grid), 32..35
#define VEIL_TEX_BLACKBODY 31       // blackbody colour and ln Y by temperature (1D)
#define VEIL_TEX_VOLUME_NEIGHBOURHOOD                                                              \
    36                              // mean density per 8^3 voxels (depth-aware octaves), 36..39
#define VEIL_TEX_SCATTERED_LIGHT 40 // scattered-light cache: mean radiance (40), P1 flux (41)
#define VEIL_IMG_FOG_RADIANCE 4
#define VEIL_IMG_FOG_TRANSMITTANCE 5
#define VEIL_IMG_VOLUME_LIGHT 6
#define VEIL_IMG_VOLUME_LIGHT_STATE 7 // FogDepthMap: each column's march between dispatches
#define VEIL_MAX_VOLUMES 4
// stochastic transparency (src/oit/stochastic): S-choose-R mask table
#define VEIL_SSBO_STOCH_MASKS 4

#define VEIL_MAX_LIGHTS 8

#define VEIL_SSBO_SHADOW_SLICES 12 // transmittance-slicemap: light-space slice-map words
// Shadow `volume`: per caster and light clamp depth or culled flag; the camera's receivers
// voxelized into each light's slice map; the opaque map's farthest depth per column.
#define VEIL_SSBO_SHADOW_VOLUME_CASTERS 13
#define VEIL_SSBO_SHADOW_VOLUME_RECEIVERS 14
#define VEIL_SSBO_SHADOW_VOLUME_OCCLUDERS 15
#define VEIL_SSBO_SHADOW_VOLUME_BOUNDS 16
// ... and classify.comp's per caster and light partial reductions (farthest occluder bits,
// farthest receiver slice + 1).
#define VEIL_SSBO_SHADOW_VOLUME_FOOTPRINTS 24
// ... and the volumes' geometry: every opaque object's vertices in world space, their source
// (mesh position, object), the objects' model matrices, the casters' adjacency (world vertex
// indices) and triangle ranges, the indirect commands with the surviving casters' work list,
// and the volumes' triangles (silhouette.comp -> volume.vert).
#define VEIL_SSBO_SHADOW_VOLUME_WORLD 17
#define VEIL_SSBO_SHADOW_VOLUME_SOURCE 18
#define VEIL_SSBO_SHADOW_VOLUME_MODELS 19
#define VEIL_SSBO_SHADOW_VOLUME_ADJACENCY 20
#define VEIL_SSBO_SHADOW_VOLUME_RANGES 21
#define VEIL_SSBO_SHADOW_VOLUME_DRAW 22
#define VEIL_SSBO_SHADOW_VOLUME_TRIANGLES 23

// Voxelization (src/voxelize, shaders/voxelize): slice-map words, per-column local-slicing
// ranges (near, far pairs), triangle soup, per-axis maps of three-axis voxelization.
#define VEIL_SSBO_VOX_WORDS 8
#define VEIL_SSBO_VOX_RANGE 9
#define VEIL_SSBO_VOX_TRIS 10
#define VEIL_SSBO_VOX_AXIS0 11
// (voxelization runs outside the frame: its slots may coincide with the fog's)
#define VEIL_TEX_VOX0 16
#define VEIL_TEX_VOX_RANGE 24

// The compute rasterizer of the transparent pass (src/frame/stages/compute_raster.*): an object's mesh
// buffers as SSBOs (frame::dispatchObjects, shaders/frame/raster_surface.glsl), and its own
// triangle records, counters, per-tile starts, per-(batch, tile) offsets and tile lists.
#define VEIL_SSBO_MESH_POSITIONS 25
#define VEIL_SSBO_MESH_NORMALS 26
#define VEIL_SSBO_MESH_UVS 27
#define VEIL_SSBO_MESH_SIZES 28
#define VEIL_SSBO_MESH_INDICES 29
#define VEIL_SSBO_RASTER_TRIANGLES 30
#define VEIL_SSBO_RASTER_COUNTERS 31
#define VEIL_SSBO_RASTER_TILE_STARTS 0
#define VEIL_SSBO_RASTER_BIN_OFFSETS 3
#define VEIL_SSBO_RASTER_TILE_LISTS 7
// The triangle records' attributes: the voxelization's slot (its passes bind their own).
#define VEIL_SSBO_RASTER_ATTRIBUTES 8

#define VEIL_ATTR_POSITION 0
#define VEIL_ATTR_NORMAL 1
#define VEIL_ATTR_UV 2
#define VEIL_ATTR_SIZE 3

#define VEIL_LIGHT_DIRECTIONAL 0
#define VEIL_LIGHT_SPOT 1
#define VEIL_LIGHT_POINT 2

#endif
