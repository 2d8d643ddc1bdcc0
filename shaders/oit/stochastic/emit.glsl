// OIT techniques `stochastic`, `stochastic-alpha`, `stochastic-depth` ([Enderton11], Enderton et al.
// 2011): oitEmit() for one geometry pass, chosen by STOCH_KIND (set per pass by
// src/oit/stochastic/stochastic.cpp):
//   STOCH_KIND 0  total alpha [Enderton11 sec. 3.3 / 3.5 step 2]: multiplicative blend into an MSAA
//                 RGBA16F target, rgb *= 1 - a + a*T (exact per-channel background
//                 modulation, [McGuire16 Eq. 2]), a *= 1 - a_eff [Enderton11 Eq. 5].
//   STOCH_KIND 1  stochastic color ([Enderton11 sec. 3.1, 3.5] basic step 3): gl_SampleMask from the
//                 S-choose-R table, z-test with depth writes, stores (c_eff, 1) per sample.
//   STOCH_KIND 2  stochastic depth ([Enderton11 sec. 3.5] depth-based step 3): same mask, depth only.
//   STOCH_KIND 3  accumulation [Enderton11 sec. 3.5 step 4]: additive (a_eff c_eff, a_eff) = (radiance,
//                 a_eff) into the samples where z_fragment <= z_buffer [Enderton11 Eq. 4/6].
//
// Colored transmission T: the stochastic coverage (and the correction alpha, [Enderton11 Eq. 5]) use
// the net coverage a_eff = a * (1 - avg(T)), the part of the background a surface removes
// on average; the colour it stands for is c_eff = radiance / a_eff, so a_eff * c_eff is the
// emitted radiance. Alpha-corrected and depth-based variants modulate the background by the
// exact per-channel product of (1 - a + a*T) (kind 0), as [McGuire16 Listing 1] does. The basic
// variant has no total-alpha pass: its background weight is the fraction of empty samples,
// i.e. T enters only through its average (grey). A surface with a_eff = 0 (T = 1) never
// covers a sample: the basic and alpha-corrected variants drop its radiance, the depth-based
// one still adds it (kind 3 uses no mask).
//
// Fog: this emit cannot be called from a compute shader (it needs rasterized samples,
// gl_SampleMask and fixed-function blending). A fog marcher must instead draw its
// per-pixel result as one more camera-facing fragment at a representative depth through
// transparent.frag's programs; the technique documents that as a limitation.

#include "../fragment.glsl"

#ifndef STOCH_KIND
#error "stochastic emit needs STOCH_KIND (0..3), set by the technique per geometry pass"
#endif

#include "../../common/bindings.h"

layout(location = 0) out vec4 oitOut;

#if STOCH_KIND == 1 || STOCH_KIND == 2
// [Enderton11 sec. 5]: S-choose-R masks from a precomputed table (src/oit/cpu/stochastic.cpp).
layout(std430, binding = VEIL_SSBO_STOCH_MASKS) readonly buffer StochMasks {
    uint stochOffset[33];
    uint stochCount[33];
    uint stochMask[];
};
uniform uint stochSeed;    // pass::Context::seed
uniform uint stochGroup;   // which table mask this pass draws from (a new one per group)
uniform int stochShift;    // first mask bit used by this pass
uniform int stochBits;     // N = bits per table mask (samples x passes sharing one mask)
uniform int stochSamples;  // S = MSAA samples of this pass

// Mirrors veil::oit::cpu::stochasticHash (PCG output permutation).
uint stochHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// [Enderton11 sec. 6]: pixel and depth in the seed so every surface of a pixel gets an independent
// mask ("seeding by fragment z is effective for still images"). Not the primitive id: the two
// triangles of one flat surface meeting inside a pixel would draw independent masks, and
// alpha correction then loses the pixel whenever their coverages miss both masks ([Enderton11 sec. 4.1],
// the "otherwise 0" case). The depth is rounded to 15 mantissa bits so both triangles of a
// flat surface agree despite interpolation rounding.
uint stochFragmentHash() {
    uint h = stochHash(stochSeed + stochHash(stochGroup));
    h = stochHash(h + ((floatBitsToUint(gl_FragCoord.z) + 0x80u) >> 8u));
    h = stochHash(h + uint(gl_FragCoord.y));
    return stochHash(h + uint(gl_FragCoord.x));
}

// Sample mask of this pass; 0 when the fragment covers no sample.
uint stochSampleMask(float alphaEff) {
    uint h = stochFragmentHash();
    // [Enderton11 sec. 3.1]: R = floor(alpha * N + xi), stratified coverage count.
    float xi = float(stochHash(h) >> 8u) * (1.0 / 16777216.0);
    int r = min(int(floor(clamp(alphaEff, 0.0, 1.0) * float(stochBits) + xi)), stochBits);
    uint mask = stochMask[stochOffset[r] + stochHash(stochHash(h)) % stochCount[r]];
    uint passBits = stochSamples >= 32 ? 0xFFFFFFFFu : ((1u << uint(stochSamples)) - 1u);
    return (mask >> uint(stochShift)) & passBits;
}
#endif

void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    float alphaEff = alpha * (1.0 - (transmission.r + transmission.g + transmission.b) / 3.0);
#if STOCH_KIND == 0
    oitOut = vec4(vec3(1.0 - alpha) + alpha * transmission, 1.0 - alphaEff);
#elif STOCH_KIND == 1 || STOCH_KIND == 2
    uint m = stochSampleMask(alphaEff);
    if (m == 0u) discard;
    gl_SampleMask[0] = int(m);
#if STOCH_KIND == 1
    // Winner-take-all colour; clamp keeps tiny a_eff inside RGBA16F.
    oitOut = vec4(min(radiance / max(alphaEff, 1e-6), vec3(60000.0)), 1.0);
#else
    oitOut = vec4(0.0);
#endif
#else
    oitOut = vec4(radiance, alphaEff);
#endif
}
