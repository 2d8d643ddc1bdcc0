// TEMPLATE emit include of a new OIT technique (src/oit/_template/template.h): defines the one
// function surfaces and the fog call, with the same contract for every technique:
//   radiance      reflected/emitted radiance already multiplied by coverage alpha
//   alpha         coverage
//   transmission  T in [0,1]^3 ([McGuire16 Eq. 2]: the background is modulated by 1 - a + a T)
//   viewDepth     distance along the view axis
// This one blends unsorted with dual-source modulation, scaling coverage by a property.

#include "../fragment.glsl"

uniform float templateOpacityScale;

layout(location = 0, index = 0) out vec4 oitOutRadiance;
layout(location = 0, index = 1) out vec4 oitOutModulation;

void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    float s = templateOpacityScale;
    // radiance is premultiplied by alpha: scaling alpha scales it too.
    oitOutRadiance = vec4(radiance * s, 1.0);
    float a = alpha * s;
    oitOutModulation = vec4(vec3(1.0 - a) + a * transmission, 1.0);
}
