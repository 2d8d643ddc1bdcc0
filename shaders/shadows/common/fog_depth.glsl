// Receivers' side of FogDepthMap (src/shadows/common/fog_depth.h): exp(-optical depth) of the
// grid density volumes from the light to normalized depth `depth` in view v, read from the
// cumulative optical depth per slice boundary (fog_depth.comp), linear between slice boundaries
// and between fog columns. The technique's prepareReceiver sets shadowFog (1 when this frame's
// volumes were marched) and shadowFogSlices.
#include "views.glsl"

layout(binding = VEIL_TEX_SHADOW2) uniform sampler3D shadowFogTau;
uniform int shadowFog;
uniform int shadowFogSlices;

float shadowFogTransmittance(int v, vec2 uv, float depth) {
    if (shadowFog == 0) return 1.0;
    float slices = float(shadowFogSlices);
    float fs = clamp(depth, 0.0, 1.0) * slices;
    float z = (float(v) * (slices + 1.0) + fs + 0.5) / (shadows.mapSize.z * (slices + 1.0));
    return exp(-texture(shadowFogTau, vec3(uv, z)).r);
}
