// OIT technique `wboit`: weighted blended OIT [McGuire13] with the depth weight
// of [McGuire16 Eq. 5]. Two targets, summed/multiplied by fixed-function blending:
//   RT0 (RGBA16F, ONE/ONE):               A = w * (alpha * L_r, netCoverage)      [McGuire16 Eq. 4]
//   RT1 (R16F,  ZERO/ONE_MINUS_SRC_COLOR): r = prod (1 - netCoverage)  (revealage)
// Colored transmission: like [McGuire16 Listing 1], T enters only through the scalar net coverage
//   netCoverage = alpha * (1 - mean(T)),
// so the background is modulated by a grey revealage, not per channel; a surface with T = 1
// (fully clear) contributes no weight and its reflections vanish in the resolve. The
// phenomenological technique ([McGuire16] full model) keeps the colored beta instead.
//
// Per-pixel contributions (the fog) come from compute through the same oitEmit()
// (OIT_COMPUTE, shaders/oit/fragment.glsl: images, the two blend equations in the shader), at
// the window depth the caller gives (oitWindowDepth; the fog's representative depth).

#include "../fragment.glsl"

OIT_TARGET(0, rgba16f, oitOutAccum);
OIT_TARGET(1, r16f, oitOutRevealage);

void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    float netCoverage = alpha * (1.0 - dot(transmission, vec3(1.0 / 3.0))); // [McGuire16 Listing 1]
    // [McGuire16 Eq. 5]: w = clamp([10 (1 - 0.99 f) alpha (1 - tbar)]^3, 0.01, 30), f = window z.
    float t = 10.0 * (1.0 - 0.99 * oitWindowDepth) * netCoverage;
    float w = clamp(t * t * t, 0.01, 30.0);
    OIT_WRITE(oitOutAccum, vec4(radiance, netCoverage) * w, oitBlendAdd);
    OIT_WRITE(oitOutRevealage, vec4(netCoverage), oitBlendModulate);
}
