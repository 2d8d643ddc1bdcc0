#include "../common/bindings.h"

// The one contribution every OIT technique takes (docs/architecture.md "Two GLSL interfaces join techniques without joining their code"): each technique's emit.glsl defines
//     void oitEmit(OitFragment f);
// Transparent surfaces fill every field (shaders/frame/transparent.frag); the fog's emission
// pass (shaders/volume/fog_emit.frag) fills the first four through oitFragment(), one per
// pixel. A technique reads what its model needs and ignores the rest (the compiler drops
// unused fields), so no technique needs an entry point or a uniform of its own in the
// callers.
struct OitFragment {
    vec3 radiance;     // reflected + emitted radiance, premultiplied by coverage alpha
    float alpha;       // coverage
    vec3 transmission; // T in [0,1]^3; the background is modulated by 1 - a + a T [McGuire16 Eq. 2]
    float viewDepth;   // distance along the view axis
    // Surfaces only (defaults for the fog):
    bool surface;      // false for a medium's per-pixel contribution (no geometry, no material)
    bool particle;     // a camera-facing billboard (phenomenological's low-resolution pass)
    float collimation; // c of [McGuire16 sec. 4.1] (1 = collimated, no diffusion)
    float eta;         // relative index of refraction across the interface [McGuire16 Eq. 8]
    vec3 viewPos;      // view-space position and normal (refraction offset, [McGuire16 Eq. 8-9])
    vec3 viewNormal;
    float roughness;             // material roughness ([Eisemann06] thickness x roughness blur)
    vec3 attenuationColor;       // KHR_materials_volume behind the surface
    float attenuationDistance;   // 0 = no absorption
    // [McGuire17 sec. 6] (inferred AO): the ambient part of radiance (premultiplied by alpha, as
    // radiance), and whether the material's base coverage is binary (baseMIPisBinary).
    vec3 ambient;
    bool binaryCoverage;
};

// Targets and writes of an emit include, one source for two callers:
//   fragments (transparent.frag, fog_emit.frag): OIT_TARGET declares a fragment output, and
//     OIT_WRITE assigns it; the technique's fixed-function blend state (its C++ side) does
//     the blending;
//   compute with OIT_COMPUTE defined (fog_emit.comp, one invocation per pixel, the only writer
//     of its pixel while it runs): OIT_TARGET declares an image on unit
//     VEIL_IMG_OIT_TARGET0 + location, which the technique binds (Technique::bindPerPixelEmit),
//     and OIT_WRITE applies the blend equation `blend(dst, src)` in the shader with imageLoad /
//     imageStore. The equation named in OIT_WRITE must be the one the technique's blend state
//     gives that target: oitBlendAdd for (ONE, ONE), oitBlendModulate for
//     (ZERO, ONE_MINUS_SRC_COLOR), or the technique's own.
// oitPixel is the contribution's pixel and oitWindowDepth its window depth in [0, 1]
// (gl_FragCoord for fragments; set by the compute caller before oitEmit()).
vec4 oitBlendAdd(vec4 dst, vec4 src) { return dst + src; }
vec4 oitBlendModulate(vec4 dst, vec4 src) { return dst * (vec4(1.0) - src); }
#ifdef OIT_COMPUTE
ivec2 oitPixel;
float oitWindowDepth;
#define OIT_TARGET(loc, format, name) layout(binding = VEIL_IMG_OIT_TARGET0 + loc, format) uniform image2D name
#define OIT_WRITE(name, value, blend) imageStore(name, oitPixel, blend(imageLoad(name, oitPixel), (value)))
#else
#define oitPixel ivec2(gl_FragCoord.xy)
#define oitWindowDepth gl_FragCoord.z
#define OIT_TARGET(loc, format, name) layout(location = loc) out vec4 name
#define OIT_WRITE(name, value, blend) name = (value)
#endif

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
    f.ambient = vec3(0.0);
    f.binaryCoverage = false;
    f.attenuationColor = vec3(1.0);
    f.attenuationDistance = 0.0;
    return f;
}
