// "veil:light_visibility" of the `volume` shadow technique (src/shadows/volume): stencil
// shadow volumes (depth-fail) give an exact, per-pixel answer for the surface in the depth
// buffer. Opaque receivers (frame/opaque.frag defines VEIL_RECEIVER_AT_DEPTH) read it at their
// pixel from an R8 array with one layer per shadowed light. Transparent surfaces and fog
// samples are not the depth buffer's surface: they get the opaque shadow map's answer
// (DepthMaps, PCF), like `opaque`.
//
// params[0]: x = bias, y = PCF radius of the opaque map. params[1], params[2]: the layer of
// scene light 0..3 and 4..7 in the visibility array (-1: no volume).
#include "../common/opaque_depth.glsl"

layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray volumeVisibility;

int volumeLayer(int i) { return int(i < 4 ? shadows.params[1][i] : shadows.params[2][i - 4]); }

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (!shadowLightHasMap(i)) return;
#ifdef VEIL_RECEIVER_AT_DEPTH
    int layer = volumeLayer(i);
    if (layer >= 0) {
        radiance *= texelFetch(volumeVisibility, ivec3(gl_FragCoord.xy, layer), 0).r;
        return;
    }
#endif
    radiance *= opaqueVisibility(i, P, N, L);
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (shadowLightHasMap(i)) radiance *= opaqueVisibilityFast(i, P);
}

#include "../common/visibility_values.glsl"
