// What the frame gives the compute rasterizer's fine stage (shaders/frame/compute_raster/
// fine.comp): surfaceLoad() sets the material and the interpolated inputs of
// frame/material.glsl from a setup record (frame/raster_setup.glsl) and interpolated
// attributes, and transparentFragment() (frame/transparent_surface.glsl, the body of
// transparent.frag) shades them: the same shading as the hardware path, one source.
#include "raster_layout.glsl"
#define SURFACE_FROM_RECORD 1
#include "transparent_surface.glsl"

void surfaceLoad(vec4 r[SURFACE_RECORD_VEC4S], float a[SURFACE_ATTRIBUTES]) {
    baseColor = r[0].rgb;
    roughness = r[0].a;
    emission = r[1].rgb;
    metalness = r[1].a;
    transmission = r[2].rgb;
    coverage = r[2].a;
    attenuationColor = r[3].rgb;
    attenuationDistance = r[3].a;
    collimation = r[4].x;
    ior = r[4].y;
    coverageEdge = r[4].z;
    billboard = r[5].x > 0.5;
    binaryCoverage = r[5].y > 0.5;
    vWorldPos = vec3(a[0], a[1], a[2]);
    vNormal = vec3(a[3], a[4], a[5]);
    vUv = vec2(a[6], a[7]);
    vViewDepth = a[8];
}
