// Four-moment reconstruction of the absorbance in front of a depth ([Munstermann18 Algorithm 2] with m =
// 4, i.e. the Hamburger 4MSM of [Peters15] applied to absorbance, [Munstermann18 sec. 6]),
// written for the shadow maps with its own names (the OIT moment technique's include may be
// in the same program with another moment count).
//
// Given the moments b = (b0, b1..b4) of the absorbance distribution over depth z in [-1, 1]
// and a receiver depth zf: bias the normalized moments toward the moments of a uniform-ish
// point set (docs/oit.md#moment-constants: (0, 0.375, 0, 0.375) for float32 storage in the 2017 [-1,1]
// form; "bias about 6e-5 toward (0, 0.628, 0, 0.628) for 16-bit optimized storage"), solve
// the 3x3 Hankel system H q = (1, zf, zf^2) (Cholesky), take the roots x1, x2 of
// q0 + q1 x + q2 x^2, and build the three-point distribution at (zf, x1, x2) with the first
// three moments: weight w_i = (b2 - b1 (x_j + x_k) + x_j x_k) / ((x_i - x_j)(x_i - x_k)).
// The absorbance in front of zf is b0 (sum of the weights of the points before zf +
// beta x w(zf)); beta = 0 for shadows [Munstermann18 sec. 7.2], a property here.

// Fraction in [0, 1] of the absorbance in front of zf; `n` = (b1..b4) / b0, biased by the
// caller.
float shadowMomentFraction(vec4 n, float zf, float beta) {
    float b1 = n.x, b2 = n.y, b3 = n.z, b4 = n.w;
    // Cholesky of H = [[1, b1, b2], [b1, b2, b3], [b2, b3, b4]] = L D L^T.
    float d1 = b2 - b1 * b1;
    float l21 = b1, l31 = b2;
    float l32 = (b3 - b1 * b2) / d1;
    float d2 = b4 - b2 * b2 - l32 * l32 * d1;
    // Solve L D L^T q = (1, zf, zf^2).
    float y1 = 1.0, y2 = zf - l21 * y1, y3 = zf * zf - l31 * y1 - l32 * y2;
    float q3 = y3 / d2, q2 = y2 / d1 - l32 * q3, q1 = y1 - l21 * q2 - l31 * q3;
    // Roots of q1 + q2 x + q3 x^2 (the numerically stable pair).
    float disc = max(q2 * q2 - 4.0 * q3 * q1, 0.0);
    float t = -0.5 * (q2 + (q2 < 0.0 ? -sqrt(disc) : sqrt(disc)));
    float xa = t / q3, xb = q1 / t;
    float x1 = min(xa, xb), x2 = max(xa, xb);
    // Weights of the three points with moments (1, b1, b2).
    float w0 = (b2 - b1 * (x1 + x2) + x1 * x2) / ((zf - x1) * (zf - x2));
    float w1 = (b2 - b1 * (zf + x2) + zf * x2) / ((x1 - zf) * (x1 - x2));
    float w2 = (b2 - b1 * (zf + x1) + zf * x1) / ((x2 - zf) * (x2 - x1));
    float front = beta * w0 + (x1 < zf ? w1 : 0.0) + (x2 < zf ? w2 : 0.0);
    // A degenerate solve (NaN/Inf: one surface, the Hankel matrix of rank one, when the bias is
    // too small for float32: docs/oit.md#moment-constants) falls back to the single-surface answer: all of
    // the absorbance is at the mean depth b1. (Falling back to beta, as the OIT does, would
    // light the shadow of a lone pane.)
    if (isnan(front) || isinf(front)) return zf > b1 ? 1.0 : beta;
    return clamp(front, 0.0, 1.0);
}
