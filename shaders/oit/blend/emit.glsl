// OIT technique `blend`: unsorted alpha blending in submission order, the single-pass
// baseline every other technique is compared against. Dual-source blending lets the
// background be modulated per channel:  dst = src0 + src1 * dst,  with
//   src0 = premultiplied reflected radiance (alpha * L_r)
//   src1 = 1 - alpha + alpha * T   ([McGuire16 Eq. 2]: the surface's factor of beta)
// which is exact when surfaces arrive back to front and wrong otherwise.

// Per-pixel contributions from compute (OIT_COMPUTE, shaders/oit/fragment.glsl): the same
// equation on the HDR image, dst = src0 + src1 * dst (alpha kept, as blend's alpha is
// (ZERO, ONE)).

#include "../fragment.glsl"

#ifdef OIT_COMPUTE
OIT_TARGET(0, rgba16f, oitHdr);
#else
layout(location = 0, index = 0) out vec4 oitOutRadiance;
layout(location = 0, index = 1) out vec4 oitOutModulation;
#endif

// radiance: reflected/emitted radiance already multiplied by coverage alpha.
// alpha: coverage. transmission: T in [0,1]^3. viewDepth: distance along the view axis.
void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    vec3 modulation = vec3(1.0 - alpha) + alpha * transmission;
#ifdef OIT_COMPUTE
    vec4 dst = imageLoad(oitHdr, oitPixel);
    imageStore(oitHdr, oitPixel, vec4(radiance + modulation * dst.rgb, dst.a));
#else
    oitOutRadiance = vec4(radiance, 1.0);
    oitOutModulation = vec4(modulation, 1.0);
#endif
}
