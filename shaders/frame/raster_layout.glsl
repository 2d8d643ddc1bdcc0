// Sizes of what frame/raster_setup.glsl hands the compute rasterizer per vertex and per
// object (its records' layout), for the rasterizer's stages that only move records.
#define SURFACE_ATTRIBUTES 9   // world position, normal, uv, view depth
#define SURFACE_RECORD_VEC4S 6 // the object's material
