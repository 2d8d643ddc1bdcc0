// 16-bit quantization of four normalized power moments (b1, b2, b3, b4) / b0 on [-1, 1]
// depth (MOMENTS-NOTES.md, 002 section 4.1 / Peters et al. 2017), shared by the moment OIT's
// 16-bit storage and the moment shadow maps' 16-bit storage. The CPU reference is
// src/oit/cpu (quantizePower4), tested in tests/unit/oit_moment_test.cpp.
// MOMENTS-NOTES.md: odd (b1, b3) and even (b2, b4) 2x2 transforms; see cpu::quantizePower4.
vec4 momentQuantize4(vec4 n) { // n = (b1, b2, b3, b4) / b0
    const float s3 = 1.7320508075688772;
    return vec4(1.5 * n.x - 2.0 * n.z + 0.5, 0.5 * s3 * n.x - 2.0 * s3 / 9.0 * n.z + 0.5,
                4.0 * n.y - 4.0 * n.w, 0.5 * n.y + 0.5 * n.w);
}
vec4 momentDequantize4(vec4 q) {
    const float s3 = 1.7320508075688772;
    const float detOdd = 1.5 * (-2.0 * s3 / 9.0) + 2.0 * (0.5 * s3);
    float o0 = q.x - 0.5, o1 = q.y - 0.5;
    return vec4(((-2.0 * s3 / 9.0) * o0 + 2.0 * o1) / detOdd, (0.5 * q.z + 4.0 * q.w) / 4.0,
                (-(0.5 * s3) * o0 + 1.5 * o1) / detOdd, (-0.5 * q.z + 4.0 * q.w) / 4.0);
}

