// A transparent surface's contribution at one fragment, shaded as in the opaque pass, for the
// active OIT technique's oitEmit() (docs/architecture.md "Two GLSL interfaces join techniques
// without joining their code"). One source for the two rasterizers of the transparent pass:
// the hardware one (frame/transparent.frag) and the compute one (frame/compute_raster/fine.comp
// through frame/raster_surface.glsl, with SURFACE_FROM_RECORD). False: the fragment is
// discarded (no coverage, or a binary-coverage material's opaque interior).
#include "../common/camera.glsl"
#include "material.glsl"
#include "shading.glsl"
#include "veil:oit_emit"

bool transparentFragment(out OitFragment f) {
    vec3 V = viewVector(vWorldPos);
    vec3 N = facingNormal(V);
    SurfaceMaterial m = currentMaterial();
    float alpha = surfaceCoverage(); // m.alpha with the particles' soft round falloff
    if (alpha <= 0.0) return false;
    // A binary-coverage material's alpha = 1 interior was drawn opaque [McGuire17 sec. 6].
    if (binaryCoverage && alpha >= 1.0) return false;
    // Light that is transmitted is not diffusely reflected.
    float diffuseWeight = 1.0 - maxComponent(m.transmission);
    vec3 reflected = shadeSurface(m, vWorldPos, N, V, diffuseWeight);
    f = oitFragment(reflected * alpha, alpha, m.transmission, vViewDepth);
    f.surface = true;
    f.particle = billboard;
    f.collimation = collimation;
    // Relative index eta = eta_before / eta_after [McGuire16 Eq. 8]: entering through a face whose
    // outward normal faces the viewer, leaving through one that faces away.
    f.eta = dot(vNormal, V) >= 0.0 ? 1.0 / ior : ior;
    f.viewPos = (camera.view * vec4(vWorldPos, 1.0)).xyz;
    f.viewNormal = normalize(mat3(camera.view) * N);
    f.roughness = roughness;
    f.attenuationColor = attenuationColor;
    f.attenuationDistance = attenuationDistance;
    f.ambient = ambientReflection(m, diffuseWeight) * alpha;
    f.binaryCoverage = binaryCoverage;
    return true;
}
