// Moment-based reconstruction of the absorbance in front of a depth [Munstermann18 Algorithms 1 and 2],
// single precision; GLSL port of src/oit/cpu/moments.cpp (the double reference it is tested
// against) without the reference's Newton polishing.
// Needs: common/camera.glsl included before, MOMENT_COUNT (m) and one of MOMENT_POWER /
// MOMENT_TRIG.
//   MOMENT_POWER: b[0..m] real power moments, m in {4, 6, 8}
//   MOMENT_TRIG:  b[0] real, b[1..m] complex (vec2), m in {3, 4}
#ifndef MOMENT_COUNT
#error "moment_math.glsl needs MOMENT_COUNT"
#endif

uniform float momentOverestimation; // beta, [Munstermann18 sec. 3.2]
uniform float momentBias;           // alpha of the biasing (docs/oit.md#moment-constants)
// power: b*_1..b*_m, a define (MOMENT_BIAS_VECTOR float[8](...)) set by the technique
const float momentBiasVector[8] = MOMENT_BIAS_VECTOR;
uniform float momentWrappingZone; // theta, [Munstermann18 Eq. 5]
uniform vec2 momentDepthRange;    // [zMin, zMax] of the log warp [Munstermann18 sec. 3.3];
                                  // x <= 0: the camera's near/far (common/camera.glsl)

const float MOMENT_PI = 3.14159265358979;

// [Munstermann18 sec. 3.3]: logarithmic depth warp to [-1, 1].
float momentWarp(float viewDepth) {
    vec2 range = momentDepthRange.x > 0.0 ? momentDepthRange : camera.viewport.zw;
    float lo = log(range.x), hi = log(range.y);
    return clamp((log(max(viewDepth, 1e-30)) - lo) / (hi - lo) * 2.0 - 1.0, -1.0, 1.0);
}

// [Munstermann18 Eq. 5]
vec2 momentCircle(float z) {
    float phi = (2.0 * MOMENT_PI - momentWrappingZone) * 0.5 * (z + 1.0);
    return vec2(cos(phi), sin(phi));
}

// Absorbance of one surface [Munstermann18 sec. 3.1], finite for alpha = 1.
float momentSurfaceAbsorbance(float alpha) { return -log(1.0 - clamp(alpha, 0.0, 0.9999999)); }

#ifdef MOMENT_POWER
const int MOMENT_N = MOMENT_COUNT / 2 + 1;

vec2 momentSolveQuadratic(float c0, float c1, float c2) {
    float disc = max(c1 * c1 - 4.0 * c2 * c0, 0.0);
    float t = -0.5 * (c1 + (c1 < 0.0 ? -sqrt(disc) : sqrt(disc)));
    return t == 0.0 ? vec2(0.0) : vec2(t / c2, c0 / t);
}

// Largest, smallest root of t^3 + 3 cbar t + dbar (three real roots assumed).
vec2 momentDepressedRoots(float cbar, float dbar) {
    float mc = max(-cbar, 0.0);
    float m = sqrt(mc);
    float phi = atan(sqrt(max(4.0 * mc * mc * mc - dbar * dbar, 0.0)), -dbar) / 3.0;
    return vec2(2.0 * m * cos(phi), 2.0 * m * cos(phi + 2.0 * MOMENT_PI / 3.0));
}

// Blinn's cubic [Blinn07], see moment_solvers.cpp: c0 + c1 x + c2 x^2 + c3 x^3.
vec3 momentSolveCubic(float c0, float c1, float c2, float c3) {
    float A = c3, B = c2 / 3.0, C = c1 / 3.0, D = c0;
    float d1 = A * C - B * B, d2 = A * D - B * C, d3 = B * D - C * C;
    vec2 ta = momentDepressedRoots(d1, -2.0 * B * d1 + A * d2);
    float tl = abs(ta.x - B) >= abs(ta.y - B) ? ta.x : ta.y;
    float lt = tl - B, ls = A;
    vec2 td = momentDepressedRoots(d3, -2.0 * C * d3 + D * d2);
    float tsm = abs(td.x - C) >= abs(td.y - C) ? td.x : td.y;
    float st = D, ss = tsm - C;
    float E = ls * ss, F = -lt * ss - ls * st, G = lt * st;
    float mt = C * F - B * G, ms = C * E - B * F;
    return vec3(lt / ls, ss != 0.0 ? st / ss : 0.0, ms != 0.0 ? mt / ms : -lt / ls);
}

// Neumark's quartic [Munstermann18 sec. 4.2]: resolvent root of smallest magnitude (Blinn), then the
// better of Herbison-Evans' two factorizations into quadratics.
vec4 momentSolveQuartic(float q0, float q1, float q2, float q3, float q4) {
    float a = q3 / q4, b = q2 / q4, c = q1 / q4, d = q0 / q4;
    vec3 ys =
        momentSolveCubic(c * c - a * b * c + a * a * d, b * b + a * c - 4.0 * d, -2.0 * b, 1.0);
    float y = ys.x;
    if (abs(ys.y) < abs(y)) y = ys.y;
    if (abs(ys.z) < abs(y)) y = ys.z;
    float by = b - y;
    float s = sqrt(max(a * a - 4.0 * y, 0.0));
    float k = sqrt(max(by * by - 4.0 * d, 0.0));
    if (a < 0.0) s = -s;
    if (by < 0.0) k = -k;
    float G1 = 0.5 * (a + s);
    float g1 = G1 != 0.0 ? y / G1 : 0.5 * (a - s);
    float H1 = 0.5 * by, h1 = 0.5 * by;
    if (s != 0.0) {
        float t = (a * by - 2.0 * c) / s;
        H1 = 0.5 * (by + t);
        h1 = 0.5 * (by - t);
    }
    if (abs(H1) >= abs(h1)) {
        if (H1 != 0.0) h1 = d / H1;
    } else {
        H1 = d / h1;
    }
    float H2 = 0.5 * (by + k);
    float h2 = H2 != 0.0 ? d / H2 : 0.5 * (by - k);
    float G2 = h2 != H2 ? (c - a * H2) / (h2 - H2) : 0.5 * a;
    float g2 = a - G2;
    float e1 = abs(G1 + g1 - a) + abs(G1 * g1 + H1 + h1 - b) + abs(G1 * h1 + g1 * H1 - c) +
               abs(H1 * h1 - d);
    float e2 = abs(G2 + g2 - a) + abs(G2 * g2 + H2 + h2 - b) + abs(G2 * h2 + g2 * H2 - c) +
               abs(H2 * h2 - d);
    bool first = e1 <= e2 || isnan(e2) || isinf(e2);
    vec2 r1 = first ? momentSolveQuadratic(H1, G1, 1.0) : momentSolveQuadratic(H2, G2, 1.0);
    vec2 r2 = first ? momentSolveQuadratic(h1, g1, 1.0) : momentSolveQuadratic(h2, g2, 1.0);
    return vec4(r1, r2);
}

// [Munstermann18 Algorithm 1] on b / b_0 (biased), returning the normalized absorbance in [0, 1].
float momentAbsorbanceNormalized(float b[MOMENT_COUNT + 1], float zf) {
    float nb[MOMENT_COUNT + 1];
    nb[0] = 1.0;
    for (int j = 1; j <= MOMENT_COUNT; ++j)
        nb[j] = mix(b[j] / b[0], momentBiasVector[j - 1], momentBias);
    // Hankel system by LDL^T (the Cholesky decomposition without square roots).
    float L[MOMENT_N * MOMENT_N];
    float D[MOMENT_N];
    float q[MOMENT_N];
    for (int j = 0; j < MOMENT_N; ++j) {
        float dj = nb[2 * j];
        for (int k = 0; k < j; ++k)
            dj -= L[j * MOMENT_N + k] * L[j * MOMENT_N + k] * D[k];
        D[j] = dj;
        for (int i = j + 1; i < MOMENT_N; ++i) {
            float lij = nb[i + j];
            for (int k = 0; k < j; ++k)
                lij -= L[i * MOMENT_N + k] * L[j * MOMENT_N + k] * D[k];
            L[i * MOMENT_N + j] = lij / dj;
        }
    }
    float zk = 1.0;
    for (int i = 0; i < MOMENT_N; ++i) {
        q[i] = zk;
        zk *= zf;
        for (int k = 0; k < i; ++k)
            q[i] -= L[i * MOMENT_N + k] * q[k];
    }
    for (int i = 0; i < MOMENT_N; ++i)
        q[i] /= D[i];
    for (int i = MOMENT_N - 1; i >= 0; --i)
        for (int k = i + 1; k < MOMENT_N; ++k)
            q[i] -= L[k * MOMENT_N + i] * q[k];
    float x[MOMENT_N];
    x[0] = zf;
#if MOMENT_COUNT == 4
    vec2 r = momentSolveQuadratic(q[0], q[1], q[2]);
    x[1] = r.x;
    x[2] = r.y;
#elif MOMENT_COUNT == 6
    vec3 r = momentSolveCubic(q[0], q[1], q[2], q[3]);
    x[1] = r.x;
    x[2] = r.y;
    x[3] = r.z;
#else
    vec4 r = momentSolveQuartic(q[0], q[1], q[2], q[3], q[4]);
    x[1] = r.x;
    x[2] = r.y;
    x[3] = r.z;
    x[4] = r.w;
#endif
    // Divided differences, expanded to monomial coefficients u; A = sum_j b_j u_j.
    float c[MOMENT_N];
    c[0] = momentOverestimation;
    for (int l = 1; l < MOMENT_N; ++l)
        c[l] = x[l] < zf ? 1.0 : 0.0;
    for (int j = 1; j < MOMENT_N; ++j)
        for (int i = MOMENT_N - 1; i >= j; --i)
            c[i] = (c[i] - c[i - 1]) / (x[i] - x[i - j]);
    float u[MOMENT_N];
    for (int k = 0; k < MOMENT_N; ++k)
        u[k] = 0.0;
    u[0] = c[MOMENT_N - 1];
    // Horner in polynomial arithmetic: u <- u * (z - x_i) + c_i, i = N-2 .. 0. Written with
    // ascending loop counters (llvmpipe 22.3 miscompiled the descending nested form).
    for (int s = 0; s < MOMENT_N - 1; ++s) {
        int i = MOMENT_N - 2 - s;
        float xi = x[i];
        float prev = 0.0;
        for (int k = 0; k < MOMENT_N; ++k) {
            float uk = u[k];
            u[k] = prev - xi * uk;
            prev = uk;
        }
        u[0] += c[i];
    }
    float a = 0.0;
    for (int j = 0; j < MOMENT_N; ++j)
        a += nb[j] * u[j];
    return a;
}
#endif // MOMENT_POWER

#include "moment_trig.glsl"

// A(z_f, b, beta) in [0, b_0]; a failed solve (NaN/Inf) falls back to beta * b_0.
float momentAbsorbance(float b[MOMENT_STORED + 1], float zf) {
    if (!(b[0] > 1e-7)) return 0.0; // [Munstermann18 sec. 3.2]: early return for b_0 = 0
    float a = momentAbsorbanceNormalized(b, zf);
    if (isnan(a) || isinf(a)) a = momentOverestimation;
    return b[0] * clamp(a, 0.0, 1.0);
}
