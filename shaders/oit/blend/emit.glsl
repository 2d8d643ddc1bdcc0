// OIT technique `blend`: unsorted alpha blending in submission order, the single-pass
// baseline every other technique is compared against. Dual-source blending lets the
// background be modulated per channel:  dst = src0 + src1 * dst,  with
//   src0 = premultiplied reflected radiance (alpha * L_r)
//   src1 = 1 - alpha + alpha * T   (000 Eq. 2: the surface's factor of beta)
// which is exact when surfaces arrive back to front and wrong otherwise.

#include "../fragment.glsl"

layout(location = 0, index = 0) out vec4 oitOutRadiance;
layout(location = 0, index = 1) out vec4 oitOutModulation;

// radiance: reflected/emitted radiance already multiplied by coverage alpha.
// alpha: coverage. transmission: T in [0,1]^3. viewDepth: distance along the view axis.
void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    oitOutRadiance = vec4(radiance, 1.0);
    oitOutModulation = vec4(vec3(1.0 - alpha) + alpha * transmission, 1.0);
}
