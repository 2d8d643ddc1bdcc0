// OIT technique `moment-*` ([Munstermann18]: moment-based order-independent transparency), float32 or
// half-float storage with additive blending only. Needs MOMENT_COUNT, MOMENT_POWER or
// MOMENT_TRIG, MOMENT_STORED (floats after b_0: m for power, 2m for trigonometric), OIT_PASS,
// and the image formats of the targets (MOMENT_FORMAT0..2, MOMENT_ACCUM_FORMAT: used where
// the targets are written as images from compute, OIT_COMPUTE).
//
// Pass 0 [Munstermann18 sec. 3.1]: accumulate absorbance moments (16-bit variants: storage16.glsl).
//   target 0 RGBA32F: (b_0, b_0 red, b_0 green, b_0 blue)
//   target 1 RGBA32F / RGBA16F: moments 1..4 (power b_1..b_4; trig re b_1, im b_1, re b_2,
//            im b_2)
//   target 2 RGBA32F / RGBA16F or RG16F where 6 are stored: moments 5..8 (only when
//            MOMENT_STORED > 4)
// Pass 1 [Munstermann18 sec. 3.2]: reconstruct T in front of the fragment and accumulate
//   target RGBA32F / RGBA16F: (radiance * T, alpha_eff * T)  (alpha = renormalization
//   weight, Eq. 2)
//
// Colored transmission: the moments are scalar. A surface modulates what is behind it by
// f = 1 - alpha + alpha * transmission [McGuire16 Eq. 2] per channel; the moments use the net
// coverage alpha_eff = 1 - mean(f) (like [McGuire16 Listing 1]'s netCoverage), and b_0 is also
// accumulated per channel from -ln f so that the background behind everything is modulated by
// the exact colored transmittance exp(-b_0,rgb) in the resolve. Surfaces in front of others
// occlude them by the scalar reconstruction only.
//
// Fog: its one contribution per pixel comes through this oitEmit() from compute (OIT_COMPUTE,
// shaders/oit/fragment.glsl: OIT_WRITE adds into the targets as images; the 16-bit storage
// commits directly, as one invocation owns its pixel and no fragment runs meanwhile).
#include "../fragment.glsl"

#include "moment_math.glsl"
#include "storage16.glsl"

float momentNetCoverage(float alpha, vec3 transmission, out vec3 absorbanceRgb) {
    vec3 f = clamp(vec3(1.0 - alpha) + alpha * transmission, vec3(1e-7), vec3(1.0));
    absorbanceRgb = -log(f);
    return clamp(1.0 - (f.r + f.g + f.b) / 3.0, 0.0, 0.9999999);
}

#if OIT_PASS == 0
#ifndef MOMENT_STORAGE16
OIT_TARGET(0, MOMENT_FORMAT0, oitOutMoments0);
OIT_TARGET(1, MOMENT_FORMAT1, oitOutMoments1);
#if MOMENT_STORED > 4
OIT_TARGET(2, MOMENT_FORMAT2, oitOutMoments2);
#endif
#endif

// The values pass 0 adds for one surface: b[0] = absorbance, b[1..] = weighted moments.
void momentEmitMoments(float alphaEff, float z, out float b[9]) {
    float a = momentSurfaceAbsorbance(alphaEff);
    for (int k = 0; k < 9; ++k)
        b[k] = 0.0;
    b[0] = a;
#ifdef MOMENT_POWER
    float zk = a;
    for (int k = 1; k <= MOMENT_COUNT; ++k)
        b[k] = (zk *= z);
#else
    vec2 x = momentCircle(z);
    vec2 xk = vec2(a, 0.0);
    for (int k = 1; k <= MOMENT_COUNT; ++k) {
        xk = vec2(xk.x * x.x - xk.y * x.y, xk.x * x.y + xk.y * x.x);
        b[2 * k - 1] = xk.x;
        b[2 * k] = xk.y;
    }
#endif
}

void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    vec3 absorbanceRgb;
    float alphaEff = momentNetCoverage(alpha, transmission, absorbanceRgb);
    float b[9];
    momentEmitMoments(alphaEff, momentWarp(viewDepth), b);
#if defined(MOMENT_STORAGE16) && defined(OIT_COMPUTE)
    momentAccumulate16(oitPixel, b, absorbanceRgb);
#elif defined(MOMENT_STORAGE16)
    momentPending = true;
    momentPendingB = b;
    momentPendingRgb = absorbanceRgb;
#else
    OIT_WRITE(oitOutMoments0, vec4(b[0], absorbanceRgb), oitBlendAdd);
    OIT_WRITE(oitOutMoments1, vec4(b[1], b[2], b[3], b[4]), oitBlendAdd);
#if MOMENT_STORED > 4
    OIT_WRITE(oitOutMoments2, vec4(b[5], b[6], b[7], b[8]), oitBlendAdd);
#endif
#endif
}

#else // OIT_PASS == 1
layout(binding = VEIL_TEX_OIT0 + 0) uniform sampler2D momentTex0;
layout(binding = VEIL_TEX_OIT0 + 1) uniform sampler2D momentTex1;
#if MOMENT_STORED > 4
layout(binding = VEIL_TEX_OIT0 + 2) uniform sampler2D momentTex2;
#endif
OIT_TARGET(0, MOMENT_ACCUM_FORMAT, oitOutAccum);

// Transmittance in front of view depth `viewDepth` at pixel p [Munstermann18 sec. 3.2].
float momentTransmittance(ivec2 p, float viewDepth) {
    float b[MOMENT_STORED + 1];
    vec4 t0 = texelFetch(momentTex0, p, 0), t1 = texelFetch(momentTex1, p, 0);
    b[0] = t0.x;
#if MOMENT_STORED > 4
    vec4 t2 = texelFetch(momentTex2, p, 0);
#else
    vec4 t2 = vec4(0.0);
#endif
#ifdef MOMENT_STORAGE16
    float n[8];
    momentDecode16(t1, t2, n);
    for (int k = 0; k < MOMENT_STORED; ++k)
        b[1 + k] = n[k] * t0.x;
#else
    for (int k = 0; k < 4 && k < MOMENT_STORED; ++k)
        b[1 + k] = t1[k];
    for (int k = 4; k < MOMENT_STORED; ++k)
        b[1 + k] = t2[k - 4];
#endif
    return exp(-momentAbsorbance(b, momentWarp(viewDepth)));
}

// What pass 1 adds for one contribution: (radiance * T, alpha_eff * T).
vec4 momentEmitComposite(ivec2 p, vec3 radiance, float alphaEff, float viewDepth) {
    float T = momentTransmittance(p, viewDepth);
    return vec4(radiance * T, alphaEff * T);
}

void oitEmit(OitFragment f) {
    vec3 radiance = f.radiance;
    float alpha = f.alpha;
    vec3 transmission = f.transmission;
    float viewDepth = f.viewDepth;
    vec3 absorbanceRgb;
    float alphaEff = momentNetCoverage(alpha, transmission, absorbanceRgb);
    OIT_WRITE(oitOutAccum, momentEmitComposite(oitPixel, radiance, alphaEff, viewDepth),
              oitBlendAdd);
}
#endif
