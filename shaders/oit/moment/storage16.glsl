// 16-bit storage for `moment-p4-16`, `moment-p6-16`, `moment-p8-16`, `moment-t3-16`,
// `moment-t4-16` [Munstermann18 sec. 4.1]: b_0 (and the per-channel b_0) in RGBA16F, the normalized
// moments b_k / b_0 in 16 bits each, power moments through the quantization transforms of
// docs/oit.md#moment-constants (UNORM16: p4 one RGBA16; p6 RGBA16 (odd 1-3, even 1) + RG16 (even 2-3); p8
// RGBA16 odd + RGBA16 even), trigonometric ones directly (SNORM16, [Munstermann18 sec. 5.3]: no
// transform needed). Accumulation is a
// read-modify-write under GL_ARB_fragment_shader_interlock (the technique adds the #extension
// line through its defines, right after #version).
// UNTESTED on llvmpipe (no interlock there); the quantization itself is tested on the CPU
// (tests/unit/oit_moment_test.cpp, *QuantizationRoundTrip) and, for these functions, against
// the CPU on any driver (tests/gl/oit_moment_test.cpp, Storage16TransformMatchesCpu).
#ifdef MOMENT_STORAGE16

#include "../../common/moment_quantize.glsl"

// Stored texels -> normalized moments n[0..MOMENT_STORED-1] = b_k / b_0.
void momentDecode16(vec4 t1, vec4 t2, out float n[8]) {
#if defined(MOMENT_POWER) && MOMENT_COUNT == 4
    vec4 d = momentDequantize4(t1);
    n = float[8](d.x, d.y, d.z, d.w, 0.0, 0.0, 0.0, 0.0);
#elif defined(MOMENT_POWER) && MOMENT_COUNT == 6
    vec3 odd, even;
    momentDequantize6(t1.xyz, vec3(t1.w, t2.xy), odd, even);
    n = float[8](odd.x, even.x, odd.y, even.y, odd.z, even.z, 0.0, 0.0);
#elif defined(MOMENT_POWER)
    vec4 odd, even;
    momentDequantize8(t1, t2, odd, even);
    n = float[8](odd.x, even.x, odd.y, even.y, odd.z, even.z, odd.w, even.w);
#else
    n = float[8](t1.x, t1.y, t1.z, t1.w, t2.x, t2.y, t2.z, t2.w);
#endif
}
void momentEncode16(float n[8], out vec4 t1, out vec4 t2) {
#if defined(MOMENT_POWER) && MOMENT_COUNT == 4
    t1 = momentQuantize4(vec4(n[0], n[1], n[2], n[3]));
    t2 = vec4(0.0);
#elif defined(MOMENT_POWER) && MOMENT_COUNT == 6
    vec3 odd, even;
    momentQuantize6(vec3(n[0], n[2], n[4]), vec3(n[1], n[3], n[5]), odd, even);
    t1 = vec4(odd, even.x);
    t2 = vec4(even.yz, 0.0, 0.0);
#elif defined(MOMENT_POWER)
    momentQuantize8(vec4(n[0], n[2], n[4], n[6]), vec4(n[1], n[3], n[5], n[7]), t1, t2);
#else
    t1 = vec4(n[0], n[1], n[2], n[3]);
    t2 = vec4(n[4], n[5], n[6], n[7]);
#endif
}

#if OIT_PASS == 0
#ifndef OIT_COMPUTE
layout(early_fragment_tests) in; // image stores only for fragments passing the depth test
layout(pixel_interlock_ordered) in;
#endif
layout(binding = VEIL_IMG_MOMENT0, rgba16f) uniform coherent image2D momentImg0;
#ifdef MOMENT_POWER
layout(binding = VEIL_IMG_MOMENT1, rgba16) uniform coherent image2D momentImg1;
#if MOMENT_COUNT == 6
layout(binding = VEIL_IMG_MOMENT2, rg16) uniform coherent image2D momentImg2;
#elif MOMENT_COUNT == 8
layout(binding = VEIL_IMG_MOMENT2, rgba16) uniform coherent image2D momentImg2;
#endif
#else
layout(binding = VEIL_IMG_MOMENT1, rgba16_snorm) uniform coherent image2D momentImg1;
#if MOMENT_STORED > 4
layout(binding = VEIL_IMG_MOMENT2, rgba16_snorm) uniform coherent image2D momentImg2;
#endif
#endif

#ifndef OIT_COMPUTE
// What this fragment adds, recorded by oitEmit and committed by main() below.
bool momentPending = false;
float momentPendingB[9];
vec3 momentPendingRgb;
#endif

// [Munstermann18 sec. 4.1]: multiply the stored normalized vector by b_0, add, divide by the new b_0.
void momentAccumulate16(ivec2 p, float b[9], vec3 absorbanceRgb) {
    vec4 s0 = imageLoad(momentImg0, p);
    vec4 t1 = imageLoad(momentImg1, p), t2 = vec4(0.0);
#if MOMENT_STORED > 4
    t2 = imageLoad(momentImg2, p);
#endif
    float n[8];
    momentDecode16(t1, t2, n);
    float b0 = s0.x + b[0];
    if (b0 > 0.0) {
        for (int k = 0; k < MOMENT_STORED; ++k)
            n[k] = (s0.x > 0.0 ? n[k] * s0.x : 0.0) + b[k + 1];
        for (int k = 0; k < MOMENT_STORED; ++k)
            n[k] /= b0;
        momentEncode16(n, t1, t2);
        imageStore(momentImg1, p, t1);
#if MOMENT_STORED > 4
        imageStore(momentImg2, p, t2);
#endif
    }
    imageStore(momentImg0, p, vec4(b0, s0.yzw + absorbanceRgb));
}

#ifndef OIT_COMPUTE
// GL_ARB_fragment_shader_interlock allows begin/endInvocationInterlockARB only in main(),
// outside flow control. The surface shader's main() (frame/transparent.frag, included after
// this file) is renamed by the #define below and called from this main(); its oitEmit() only
// records what to add, and the critical section commits it.
void momentSurfaceMain();
void main() {
    momentSurfaceMain();
    beginInvocationInterlockARB();
    if (momentPending)
        momentAccumulate16(ivec2(gl_FragCoord.xy), momentPendingB, momentPendingRgb);
    endInvocationInterlockARB();
}
#define main momentSurfaceMain
#endif // !OIT_COMPUTE
#endif // OIT_PASS == 0
#endif // MOMENT_STORAGE16
