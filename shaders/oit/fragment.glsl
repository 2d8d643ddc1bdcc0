// The one contribution every OIT technique takes (DESIGN.md "How fog and surfaces share one
// transparency technique"): each technique's emit.glsl defines
//     void oitEmit(OitFragment f);
// Transparent surfaces fill every field (shaders/frame/transparent.frag); the fog's emission
// pass (shaders/volume/fog_emit.frag) fills the first four through oitFragment(), one per
// pixel. A technique reads what its model needs and ignores the rest (the compiler drops
// unused fields), so no technique needs an entry point or a uniform of its own in the
// callers.
struct OitFragment {
    vec3 radiance;     // reflected + emitted radiance, premultiplied by coverage alpha
    float alpha;       // coverage
    vec3 transmission; // T in [0,1]^3; the background is modulated by 1 - a + a T (000 Eq. 2)
    float viewDepth;   // distance along the view axis
    // Surfaces only (defaults for the fog):
    bool surface;      // false for a medium's per-pixel contribution (no geometry, no material)
    bool particle;     // a camera-facing billboard (phenomenological's low-resolution pass)
    float collimation; // c of 000 section 4.1 (1 = collimated, no diffusion)
    float eta;         // relative index of refraction across the interface (000 Eq. 8)
    vec3 viewPos;      // view-space position and normal (refraction offset, 000 Eq. 8-9)
    vec3 viewNormal;
    float roughness;             // material roughness (003 thickness x roughness blur)
    vec3 attenuationColor;       // KHR_materials_volume behind the surface
    float attenuationDistance;   // 0 = no absorption
};

// A contribution with no surface: what the fog hands over per pixel.
OitFragment oitFragment(vec3 radiance, float alpha, vec3 transmission, float viewDepth) {
    OitFragment f;
    f.radiance = radiance;
    f.alpha = alpha;
    f.transmission = transmission;
    f.viewDepth = viewDepth;
    f.surface = false;
    f.particle = false;
    f.collimation = 1.0;
    f.eta = 1.0;
    f.viewPos = vec3(0.0);
    f.viewNormal = vec3(0.0, 0.0, 1.0);
    f.roughness = 0.0;
    f.attenuationColor = vec3(1.0);
    f.attenuationDistance = 0.0;
    return f;
}
