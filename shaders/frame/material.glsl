// Per-draw material uniforms (scene::Material) and the view-dependent shading inputs.
// Three callers: the fragment stage (uniforms and interpolated inputs); with SURFACE_UNIFORMS_ONLY
// a compute shader that reads an object's uniforms (the compute rasterizer's setup); with
// SURFACE_FROM_RECORD a compute shader that sets them per fragment as plain globals from the
// setup's records (frame/raster_surface.glsl: the compute rasterizer's fine stage).
#ifdef SURFACE_FROM_RECORD
#define SURFACE_VALUE
#else
#define SURFACE_VALUE uniform
#endif
#include "../common/lights.glsl"

SURFACE_VALUE vec3 baseColor;
SURFACE_VALUE float roughness;
SURFACE_VALUE float metalness;
SURFACE_VALUE vec3 emission;
SURFACE_VALUE float coverage;      // coverage alpha
SURFACE_VALUE vec3 transmission;   // T, [McGuire16 Eq. 2]
SURFACE_VALUE float collimation;   // c, [McGuire16 sec. 4.1]
SURFACE_VALUE float ior;           // eta of the medium behind the surface, [McGuire16 Eq. 8]
SURFACE_VALUE bool billboard;
// [McGuire17 sec. 6]: coverage from a binary mask whose filtered edge is coverageEdge wide (UV
// units; scene::Material::coverageEdge); binaryCoverage = baseMIPisBinary (no transmission).
SURFACE_VALUE float coverageEdge;
SURFACE_VALUE bool binaryCoverage;
// KHR_materials_volume (scene::Material): attenuationColor^(distance / attenuationDistance) is
// the transmittance of the medium behind the surface; attenuationDistance 0 = no absorption.
SURFACE_VALUE vec3 attenuationColor;
SURFACE_VALUE float attenuationDistance;
#define VEIL_MATERIAL_UNIFORMS 1

#if defined(SURFACE_FROM_RECORD)
vec3 vWorldPos;
vec3 vNormal;
vec2 vUv;
float vViewDepth;
#elif !defined(SURFACE_UNIFORMS_ONLY)
in vec3 vWorldPos;
in vec3 vNormal;
in vec2 vUv;
in float vViewDepth;
#endif

SurfaceMaterial currentMaterial() {
    SurfaceMaterial m;
    m.baseColor = baseColor;
    m.roughness = roughness;
    m.metalness = metalness;
    m.emission = emission;
    m.alpha = coverage;
    m.transmission = transmission;
    return m;
}

#ifndef SURFACE_UNIFORMS_ONLY // what reads the interpolated inputs
// Coverage alpha of this fragment: the material's, with the soft round falloff of particles
// (billboard quads: Gaussian over the quad, nothing outside the unit disc).
float surfaceCoverage() {
    float alpha = coverage;
    if (billboard) {
        float r2 = dot(vUv, vUv);
        alpha = r2 > 1.0 ? 0.0 : alpha * exp(-4.0 * r2);
    } else if (coverageEdge > 0.0) {
        vec2 d = min(vUv, 1.0 - vUv);
        alpha *= clamp(min(d.x, d.y) / coverageEdge, 0.0, 1.0);
    }
    return alpha;
}

// What a transparent surface lets through toward what is behind it (light toward a shadow
// receiver, the background toward the eye), per channel: 1 - alpha + alpha T [McGuire16 Eq. 2].
vec3 surfaceTransmittance(float alpha) { return vec3(1.0 - alpha) + alpha * transmission; }

// Shading normal facing the viewer (two-sided for thin transparent surfaces).
vec3 facingNormal(vec3 V) {
    vec3 N = normalize(vNormal);
    return dot(N, V) < 0.0 ? -N : N;
}
#endif
