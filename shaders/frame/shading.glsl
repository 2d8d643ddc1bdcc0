// Surface shading shared by the opaque and transparent passes: every light through the
// active shadow technique's visibility ("veil:light_visibility"), plus the ambient term.
#include "../common/lights.glsl"
#include "veil:light_visibility"
// shadowReceiverDerivatives() for the fragment-shader receivers (opaque.frag, transparent.frag).
#include "../shadows/common/receiver_derivatives.glsl"
// With VEIL_SURFACE_SCATTERED_LIGHT (the frame has a scattered-light cache) the diffuse lobe
// also receives the cache's scattered and emitted light (volume/scattered_light.glsl).
#include "../volume/scattered_light.glsl"

// The ambient term alone (constant irradiance times the diffuse albedo).
vec3 ambientReflection(SurfaceMaterial m, float diffuseWeight) {
    return lighting.ambient.rgb * m.baseColor * (1.0 - m.metalness) * diffuseWeight;
}

// Reflected radiance toward V: all lights times their visibility, plus the ambient term.
vec3 shadeSurface(SurfaceMaterial m, vec3 P, vec3 N, vec3 V, float diffuseWeight) {
    vec3 result = m.emission + lighting.ambient.rgb * m.baseColor * (1.0 - m.metalness) *
                                   diffuseWeight;
#ifdef VEIL_SURFACE_SCATTERED_LIGHT
    result += scatteredSurfaceLight(P, N, lighting.ambient.rgb) * m.baseColor *
              (1.0 - m.metalness) * diffuseWeight;
#endif
    for (int i = 0; i < lighting.lightCount.x; ++i) {
        vec3 L;
        vec3 e = incidentRadiance(i, P, L);
        if (dot(N, L) <= 0.0) continue;
        lightAttenuate(i, P, N, L, e);
        result += e * evaluateBrdfCos(m, N, V, L, diffuseWeight);
    }
    return result;
}

// shadeSurface with the ambient term times the ambient visibility ao (the frame's AO buffer).
vec3 shadeSurfaceOccluded(SurfaceMaterial m, vec3 P, vec3 N, vec3 V, float diffuseWeight,
                          float ao) {
    return shadeSurface(m, P, N, V, diffuseWeight) - (1.0 - ao) * ambientReflection(m, diffuseWeight);
}
