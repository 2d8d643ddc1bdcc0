#version 450 core
// Transparent casters into a stochastic shadow map (src/shadows/stochastic): the fragment
// covers R = floor(rho S + xi) of the S MSAA samples ([Enderton11 sec. 3.1] stratified count, sec. 3.6
// "rendering an MSAA z-buffer and discarding a stochastic set of samples"), a uniformly
// random R-subset chosen by gl_SampleMask, and writes its linear depth (views.glsl); the depth
// test keeps the nearest surface per sample. A sample stays at the clear depth (or an opaque
// caster's) with probability 1 - rho, so the fraction of samples behind a receiver estimates
// prod(1 - rho_i) [Enderton11 Eq. 3, 4].
//
// rho per channel: the fraction of the light a surface removes, alpha (1 - t) = 1 -
// surfaceTransmittance(alpha) ([McGuire16 Eq. 2]; the colored stochastic shadow maps write the map of
// wavelength lambda with probability rho(lambda), [McGuire16 sec. 4.3]); stochChannel < 0: one grey
// map of the channels' mean. With `caustics` rho is scaled by [McGuire16 Eq. 10-12].
//
// Random numbers: a PCG-style hash of the frame seed, the view, the texel and the fragment's
// depth ([Enderton11 sec. 6]: seeding by z gives every surface of a texel its own mask; the depth is
// rounded so the two triangles of one flat surface agree). The channel is not hashed: the
// three channels share xi and the sample order, so their masks nest (a grey surface gives
// three identical masks: no colour noise from independent channels).
#include "../../frame/material.glsl"
#include "../common/views.glsl"

uniform int shadowView;
uniform uint stochSeed;
uniform int stochSamples;   // S, at most 32
uniform int stochChannel;   // 0..2, or -1 for the grey map
uniform bool caustics;      // [McGuire16 Eq. 10-12]
uniform bool lightOrthographic;
uniform vec3 lightPosition; // spot and point lights
uniform vec3 lightDirection; // direction the light travels (directional)

uint stochHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// [McGuire16 Eq. 10-12] with the paper's eta = eta_before / eta_after: 1 / ior where light enters
// the material from air (the normal faces the light), s = clamp((ior - 1) / 2); ior where it
// leaves (the back face of a closed mesh), where Eq. 10 gives s = 0 and rho is left as it is.
// g = 2 clamp(1 - |n.w|^(128 s^2)) - 1, rho scaled by 1 + g s^0.2 (less shadow at normal
// incidence, more at grazing).
float causticScale(vec3 P) {
    vec3 w = lightOrthographic ? -lightDirection : normalize(lightPosition - P);
    float cosI = dot(normalize(vNormal), w);
    float s = cosI > 0.0 ? clamp((ior - 1.0) * 0.5, 0.0, 1.0) : 0.0;
    if (s <= 0.0) return 1.0;
    float g = 2.0 * clamp(1.0 - pow(abs(cosI), 128.0 * s * s), 0.0, 1.0) - 1.0;
    return 1.0 + g * pow(s, 0.2);
}

void main() {
    float alpha = surfaceCoverage();
    vec3 rho3 = vec3(1.0) - surfaceTransmittance(alpha);
    float rho = stochChannel < 0 ? (rho3.r + rho3.g + rho3.b) / 3.0 : rho3[stochChannel];
    if (caustics) rho *= causticScale(vWorldPos);
    rho = clamp(rho, 0.0, 1.0);

    float depth = clamp(shadowViewDepth(shadowView, vWorldPos), 0.0, 1.0);
    uint h = stochHash(stochSeed + stochHash(uint(shadowView)));
    h = stochHash(h + ((floatBitsToUint(depth) + 0x80u) >> 8u));
    h = stochHash(h + uint(gl_FragCoord.y));
    h = stochHash(h + uint(gl_FragCoord.x));

    int S = stochSamples;
    float xi = float(stochHash(h) >> 8u) * (1.0 / 16777216.0);
    int R = min(int(floor(rho * float(S) + xi)), S); // [Enderton11 sec. 3.1]: E[R] = rho S
    if (R <= 0) discard;
    uint mask;
    if (R >= S) {
        mask = S >= 32 ? 0xFFFFFFFFu : (1u << uint(S)) - 1u;
    } else {
        // A uniformly random R-subset: the R samples of smallest random key (ties by index).
        uint key[32];
        for (int i = 0; i < S; ++i) key[i] = stochHash(h + uint(i + 1) * 0x9E3779B9u);
        mask = 0u;
        for (int i = 0; i < S; ++i) {
            int rank = 0;
            for (int j = 0; j < S; ++j)
                rank += (key[j] < key[i] || (key[j] == key[i] && j < i)) ? 1 : 0;
            if (rank < R) mask |= 1u << uint(i);
        }
    }
    gl_SampleMask[0] = int(mask);
    gl_FragDepth = depth;
}
