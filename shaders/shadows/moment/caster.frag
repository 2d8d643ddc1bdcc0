#version 450 core
// Transparent casters into a light view's absorbance moment maps ([Munstermann18 sec. 6]: "an additive
// pass renders transparent shadow casters to a separate moment shadow map"), blended with
// ONE, ONE and no depth test ([Munstermann18 sec. 6]: testing against the opaque casters' depth makes
// the shadows of opaque silhouettes leak).
//
// Colour (src/shadows/moment/moment.h): per channel absorbance a_c = -ln T_c sums into
// target 0's rgb (the surfaces' total absorbance b0 per channel); their depth distribution is
// stored once, as four power moments of the mean absorbance a = (a_r + a_g + a_b) / 3 ([Munstermann18 sec. 3.1, Eq. 1] with b(z) = (1, z, z^2, z^3, z^4)) in target 1, z the linear depth along
// the view mapped to [-1, 1]. Target 0's alpha and target 2 belong to the media (media.comp).
#include "../../frame/material.glsl"
#include "../common/views.glsl"

uniform int shadowView;

layout(location = 0) out vec4 outAbsorbance;   // a_r, a_g, a_b, (media b0)
layout(location = 1) out vec4 outMoments;      // a z, a z^2, a z^3, a z^4
layout(location = 2) out vec4 outMediaMoments; // nothing from surfaces

void main() {
    float alpha = surfaceCoverage();
    if (alpha <= 0.0) discard;
    // [McGuire16 Eq. 2]: what the surface lets through, per channel; 1e-7 keeps alpha = 1, T = 0
    // finite (absorbance 16: transmittance 1e-7).
    vec3 T = clamp(surfaceTransmittance(alpha), vec3(1e-7), vec3(1.0));
    vec3 a = -log(T);
    float mean = (a.r + a.g + a.b) / 3.0;
    if (mean <= 0.0) discard;
    float z = clamp(shadowViewDepth(shadowView, vWorldPos), 0.0, 1.0) * 2.0 - 1.0;
    float z2 = z * z;
    outAbsorbance = vec4(a, 0.0);
    outMoments = mean * vec4(z, z2, z2 * z, z2 * z2);
    outMediaMoments = vec4(0.0);
}
