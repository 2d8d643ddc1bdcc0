// "veil:light_visibility" of `transmittance-slicemap` (src/shadows/transmittance_slicemap):
// [Eisemann06 sec. 3] transmittance shadow maps. Per light view, one slice map of the semi-transparent
// casters per material class c (slices.glsl); a receiver at slice s of its column gets
//     prod_c T_c^(n_c),   n_c = set slices of class c in 0 .. s - 1
// times the opaque casters' PCF map (opaque_depth.glsl). The receiver's own slice is never
// counted (a lit transparent surface does not shadow itself).
//
// params[0]: x = bias (world units), y = PCF radius, z = slices, w = 1 when local slicing
// (per-column [near, far] in the RG32F array at VEIL_TEX_SHADOW1, layer = view).
// Uniforms (prepareReceiver, from this frame's passes): slmClasses and slmClassT[c] = T_c;
// the fog's optical depth per slice (common/fog_depth.glsl, the technique's own slices): the
// grid density volumes attenuate every receiver by exp(-tau) up to its depth.
#include "../common/opaque_depth.glsl"
#include "slices.glsl"
#include "../common/fog_depth.glsl"

layout(binding = VEIL_TEX_SHADOW1) uniform sampler2DArray slmRange;
uniform int slmClasses;
uniform vec3 slmClassT[3];

// Transmittance of the transparent casters between the light and P in view v through the
// column at texel offset `o` from P's; `depth` is the receiver's depth in that column (P's own,
// or the receiver plane's there: with local slicing a column's slices can be far thinner than
// the depth step between neighbouring texels of a tilted receiver).
vec3 slmColumnTransmittance(int v, vec2 uv, float depth, ivec2 o) {
    int size = int(shadows.mapSize.x);
    ivec2 col = clamp(ivec2(uv * float(size)) + o, ivec2(0), ivec2(size - 1));
    int slices = int(shadows.params[0].z);
    vec2 r = vec2(0.0, 1.0);
    if (shadows.params[0].w > 0.5) {
        r = texelFetch(slmRange, ivec3(col, v), 0).xy * vec2(1.0, -1.0);
        if (r.x > r.y) return vec3(1.0); // no transparent caster in this column
        r.y = max(r.y, r.x + 1e-7);
    }
    float t = depth - shadows.params[0].x / shadowViewDepthScale(v);
    int s = int(floor(clamp((t - r.x) / (r.y - r.x), -1.0, 2.0) * float(slices)));
    if (s <= 0) return vec3(1.0);
    vec3 classT[3] = slmClassT;
    return slmAttenuation(v, slmClasses, size * size, (slices + 31) / 32,
                          col.y * size + col.x, min(s - 1, slices - 1), classT);
}

// Surfaces: the opaque map's PCF times the slice transmittance averaged over the same kernel,
// each tap at the receiver plane's depth in its column (shadowReceiverSlope).
vec3 slmVisibility(int light, vec3 P, vec3 N, vec3 L) {
    int v;
    vec2 uv;
    float z, w;
    if (!shadowLocate(light, P, v, uv, z, w)) return vec3(1.0);
    int r = int(shadows.params[0].y);
    vec2 slope = r > 0 ? shadowReceiverSlope(v, N, uv, w) : vec2(0.0);
    vec3 sum = vec3(0.0);
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x)
            sum += slmColumnTransmittance(v, uv, z + dot(slope, vec2(x, y)), ivec2(x, y));
    float n = float(2 * r + 1);
    return opaqueVisibility(light, P, N, L) * shadowFogTransmittance(v, uv, z) * sum / (n * n);
}

// Volume samples: one column, one opaque tap.
vec3 slmVisibilityInMedium(int light, vec3 P) {
    int v;
    vec2 uv;
    float z;
    if (!shadowLocate(light, P, v, uv, z)) return vec3(1.0);
    return opaqueVisibilityFast(light, P) * shadowFogTransmittance(v, uv, z) *
           slmColumnTransmittance(v, uv, z, ivec2(0));
}

void lightAttenuate(int i, vec3 P, vec3 N, vec3 L, inout vec3 radiance) {
    if (shadowLightHasMap(i)) radiance *= slmVisibility(i, P, N, L);
}

void lightAttenuateInMedium(int i, vec3 P, inout vec3 radiance) {
    if (shadowLightHasMap(i)) radiance *= slmVisibilityInMedium(i, P);
}

#include "../common/visibility_values.glsl"
