// [Munstermann18 Algorithm 2] (trigonometric moments, Toeplitz system, complex roots), included by
// moment_math.glsl when MOMENT_TRIG is defined. Complex numbers are vec2 (re, im).
#ifdef MOMENT_TRIG
const int MOMENT_N = MOMENT_COUNT + 1;

vec2 cmul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 cdiv(vec2 a, vec2 b) { return cmul(a, vec2(b.x, -b.y)) / dot(b, b); }
vec2 cconj(vec2 a) { return vec2(a.x, -a.y); }
vec2 csqrt(vec2 z) {
    float r = length(z);
    return vec2(sqrt(max(0.5 * (r + z.x), 0.0)),
                (z.y < 0.0 ? -1.0 : 1.0) * sqrt(max(0.5 * (r - z.x), 0.0)));
}
vec2 ccbrt(vec2 z) { // principal cube root
    float r = length(z);
    float phi = atan(z.y, z.x) / 3.0;
    return pow(r, 1.0 / 3.0) * vec2(cos(phi), sin(phi));
}

// Roots of c0 + c1 x + c2 x^2: the one of greater magnitude first [Munstermann18 sec. 5.3].
void cSolveQuadratic(vec2 c0, vec2 c1, vec2 c2, out vec2 r0, out vec2 r1) {
    vec2 s = csqrt(cmul(c1, c1) - 4.0 * cmul(c2, c0));
    if (dot(c1, s) < 0.0) s = -s;
    vec2 t = -0.5 * (c1 + s);
    bool zero = dot(t, t) == 0.0;
    r0 = zero ? vec2(0.0) : cdiv(t, c2);
    r1 = zero ? vec2(0.0) : cdiv(c0, t);
}

// Cardano on the depressed cubic, cube root of the term of greater magnitude.
void cSolveCubic(vec2 c0, vec2 c1, vec2 c2, vec2 c3, out vec2 r[3]) {
    vec2 a = cdiv(c2, c3), b = cdiv(c1, c3), d = cdiv(c0, c3);
    vec2 a2 = cmul(a, a);
    vec2 p = b - a2 / 3.0;
    vec2 q = 2.0 * cmul(a2, a) / 27.0 - cmul(a, b) / 3.0 + d;
    vec2 s = csqrt(cmul(q, q) / 4.0 + cmul(cmul(p, p), p) / 27.0);
    if (dot(-q, s) < 0.0) s = -s;
    vec2 w = -0.5 * q + s;
    vec2 u = ccbrt(w);
    const vec2 omega = vec2(-0.5, 0.86602540378);
    for (int k = 0; k < 3; ++k) {
        r[k] = dot(u, u) > 0.0 ? u - cdiv(p, 3.0 * u) - a / 3.0 : -a / 3.0;
        u = cmul(u, omega);
    }
}

// Neumark generalized to complex coefficients, resolvent root not of least magnitude.
void cSolveQuartic(vec2 q0, vec2 q1, vec2 q2, vec2 q3, vec2 q4, out vec2 r[4]) {
    vec2 a = cdiv(q3, q4), b = cdiv(q2, q4), c = cdiv(q1, q4), d = cdiv(q0, q4);
    vec2 ys[3];
    cSolveCubic(cmul(c, c) - cmul(cmul(a, b), c) + cmul(cmul(a, a), d),
                cmul(b, b) + cmul(a, c) - 4.0 * d, -2.0 * b, vec2(1.0, 0.0), ys);
    vec2 y = ys[0];
    if (dot(ys[1], ys[1]) > dot(y, y)) y = ys[1];
    if (dot(ys[2], ys[2]) > dot(y, y)) y = ys[2];
    vec2 by = b - y;
    vec2 s = csqrt(cmul(a, a) - 4.0 * y);
    vec2 k = csqrt(cmul(by, by) - 4.0 * d);
    if (dot(a, s) < 0.0) s = -s;
    if (dot(by, k) < 0.0) k = -k;
    vec2 G1 = 0.5 * (a + s);
    vec2 g1 = dot(G1, G1) > 0.0 ? cdiv(y, G1) : 0.5 * (a - s);
    vec2 H1 = 0.5 * by, h1 = 0.5 * by;
    if (dot(s, s) > 0.0) {
        vec2 t = cdiv(cmul(a, by) - 2.0 * c, s);
        H1 = 0.5 * (by + t);
        h1 = 0.5 * (by - t);
    }
    if (dot(H1, H1) >= dot(h1, h1)) {
        if (dot(H1, H1) > 0.0) h1 = cdiv(d, H1);
    } else {
        H1 = cdiv(d, h1);
    }
    vec2 H2 = 0.5 * (by + k);
    vec2 h2 = dot(H2, H2) > 0.0 ? cdiv(d, H2) : 0.5 * (by - k);
    vec2 G2 = h2 != H2 ? cdiv(c - cmul(a, H2), h2 - H2) : 0.5 * a;
    vec2 g2 = a - G2;
    float e1 = length(G1 + g1 - a) + length(cmul(G1, g1) + H1 + h1 - b) +
               length(cmul(G1, h1) + cmul(g1, H1) - c) + length(cmul(H1, h1) - d);
    float e2 = length(G2 + g2 - a) + length(cmul(G2, g2) + H2 + h2 - b) +
               length(cmul(G2, h2) + cmul(g2, H2) - c) + length(cmul(H2, h2) - d);
    bool first = e1 <= e2 || isnan(e2) || isinf(e2);
    cSolveQuadratic(first ? H1 : H2, first ? G1 : G2, vec2(1.0, 0.0), r[0], r[1]);
    cSolveQuadratic(first ? h1 : h2, first ? g1 : g2, vec2(1.0, 0.0), r[2], r[3]);
}

// [Munstermann18 sec. 5.2]: piecewise linear stand-in for the angle.
float momentPsi(vec2 x) {
    if (x.y >= 0.0) return x.x >= 0.0 ? -x.x + x.y : 2.0 - x.x - x.y;
    return x.x < 0.0 ? 4.0 + x.x - x.y : 6.0 + x.x + x.y;
}

// b = (b_0, re b_1, im b_1, ..., re b_m, im b_m): [Munstermann18 Algorithm 2] on b / b_0 with the
// biasing b_j *= 1 - alpha [Munstermann18 sec. 5.3]; returns the normalized absorbance.
float momentAbsorbanceNormalized(float b[2 * MOMENT_COUNT + 1], float zf) {
    vec2 nb[MOMENT_N];
    nb[0] = vec2(1.0, 0.0);
    for (int j = 1; j <= MOMENT_COUNT; ++j)
        nb[j] = (1.0 - momentBias) * vec2(b[2 * j - 1], b[2 * j]) / b[0];
    vec2 L[MOMENT_N * MOMENT_N];
    float D[MOMENT_N];
    for (int j = 0; j < MOMENT_N; ++j) {
        float dj = 1.0;
        for (int k = 0; k < j; ++k)
            dj -= dot(L[j * MOMENT_N + k], L[j * MOMENT_N + k]) * D[k];
        D[j] = dj;
        for (int i = j + 1; i < MOMENT_N; ++i) {
            vec2 lij = nb[i - j];
            for (int k = 0; k < j; ++k)
                lij -= cmul(L[i * MOMENT_N + k], cconj(L[j * MOMENT_N + k])) * D[k];
            L[i * MOMENT_N + j] = lij / dj;
        }
    }
    vec2 x0 = momentCircle(zf);
    vec2 q[MOMENT_N];
    vec2 xk = vec2(1.0, 0.0);
    for (int i = 0; i < MOMENT_N; ++i) {
        q[i] = xk;
        xk = cmul(xk, x0);
        for (int k = 0; k < i; ++k)
            q[i] -= cmul(L[i * MOMENT_N + k], q[k]);
    }
    for (int i = 0; i < MOMENT_N; ++i)
        q[i] /= D[i];
    for (int i = MOMENT_N - 1; i >= 0; --i)
        for (int k = i + 1; k < MOMENT_N; ++k)
            q[i] -= cmul(cconj(L[k * MOMENT_N + i]), q[k]);
    // Kernel polynomial sum_j conj(q_j) x^j (see moments.cpp).
    vec2 x[MOMENT_N];
    x[0] = x0;
#if MOMENT_COUNT == 3
    vec2 r[3];
    cSolveCubic(cconj(q[0]), cconj(q[1]), cconj(q[2]), cconj(q[3]), r);
#else
    vec2 r[4];
    cSolveQuartic(cconj(q[0]), cconj(q[1]), cconj(q[2]), cconj(q[3]), cconj(q[4]), r);
#endif
    for (int l = 1; l < MOMENT_N; ++l)
        x[l] = r[l - 1];
    // [Munstermann18 Eq. 6]
    float psi0 = momentPsi(x0), psiEnd = momentPsi(momentCircle(1.0));
    vec2 c[MOMENT_N];
    c[0] = vec2(momentOverestimation, 0.0);
    for (int l = 1; l < MOMENT_N; ++l) {
        float s = momentPsi(x[l]);
        c[l] = vec2(s < psi0 ? 1.0 : s <= psiEnd ? 0.0 : (s - psiEnd) / (7.0 - psiEnd), 0.0);
    }
    for (int j = 1; j < MOMENT_N; ++j)
        for (int i = MOMENT_N - 1; i >= j; --i)
            c[i] = cdiv(c[i] - c[i - 1], x[i] - x[i - j]);
    vec2 u[MOMENT_N];
    for (int k = 0; k < MOMENT_N; ++k)
        u[k] = vec2(0.0);
    u[0] = c[MOMENT_N - 1];
    // u <- u * (x - x_i) + c_i with ascending counters (see moment_math.glsl).
    for (int s = 0; s < MOMENT_N - 1; ++s) {
        int i = MOMENT_N - 2 - s;
        vec2 xi = x[i];
        vec2 prev = vec2(0.0);
        for (int k = 0; k < MOMENT_N; ++k) {
            vec2 uk = u[k];
            u[k] = prev - cmul(xi, uk);
            prev = uk;
        }
        u[0] += c[i];
    }
    float a = 0.0;
    for (int j = 0; j < MOMENT_N; ++j)
        a += cmul(nb[j], u[j]).x;
    return a;
}
#endif // MOMENT_TRIG
