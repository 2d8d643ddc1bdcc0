// 16-bit quantization of 4, 6 or 8 normalized power moments b_k / b0 on [-1, 1]
// depth (docs/oit.md#moment-constants, [Munstermann18 sec. 4.1] / [Peters17]), shared by the moment OIT's
// 16-bit storage and the moment shadow maps' 16-bit storage. The CPU reference is
// src/oit/cpu (quantizePower4), tested in tests/unit/oit_moment_test.cpp.
// docs/oit.md#moment-constants: odd (b1, b3) and even (b2, b4) 2x2 transforms; see cpu::quantizePower4.
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


// 6 and 8 power moments (docs/oit.md#moment-constants; CPU reference cpu::quantizePower, whose comment says
// why the offsets come after the transform). GLSL matrix constructors fill columns, so a
// row-major list M gives mat * v = v M (6 moments: row vector times matrix) and v * mat = M v
// (8 moments: matrix times column vector). Odd = (n1, n3, n5[, n7]), even = (n2, n4, n6[, n8]).
const mat3 kMomentQ6Odd = mat3(2.5, -1.87499864450, 1.26583039016, -10.0, 4.20757543111,
                               -1.47644882902, 8.0, -1.83257678661, 0.71061660238);
const mat3 kMomentQ6Even = mat3(4.0, 9.0, -0.57759806484, -4.0, -24.0, 4.61936647543, 0.0, 16.0,
                                -3.07953906655);
const mat3 kMomentQ6OddInv = mat3(-0.02877789192, 0.09995235706, 0.25893353755, 0.47635550422,
                                  0.84532580931, 0.90779616657, 1.55242808973, 1.05472570761,
                                  0.83327335647);
const mat3 kMomentQ6EvenInv = mat3(0.00001253044, -0.24998746956, -0.37498825271, 0.16668494186,
                                   0.16668494186, 0.21876713299, 0.86602540579, 0.86602540579,
                                   0.81189881793);
const vec3 kMomentQ6EvenOffset = vec3(0.0, 0.0, 0.018888946);
void momentQuantize6(vec3 odd, vec3 even, out vec3 qOdd, out vec3 qEven) {
    qOdd = kMomentQ6Odd * odd + vec3(0.5);
    qEven = kMomentQ6Even * even + kMomentQ6EvenOffset;
}
void momentDequantize6(vec3 qOdd, vec3 qEven, out vec3 odd, out vec3 even) {
    odd = kMomentQ6OddInv * (qOdd - vec3(0.5));
    even = kMomentQ6EvenInv * (qEven - kMomentQ6EvenOffset);
}

const mat4 kMomentQ8Odd = mat4(
    3.48044635732474, -27.5760737514826, 55.1267384344761, -31.5311110403183, 1.26797185782836,
    -0.928755808743913, -2.07520453231032, 1.23598848322588, -2.1671560004294, 6.17950199592966,
    -0.276515571579297, -4.23583042392097, 0.974332879165755, -0.443426830933027,
    -0.360491648368785, 0.310149466050223);
const mat4 kMomentQ8Even = mat4(
    0.280504133158527, -0.757633844606942, 0.392179589334688, -0.887531871812237,
    -2.01362265883247, 0.221551373038988, -1.06107954265125, 2.83887201588367, -7.31010494985321,
    13.9855979699139, -0.114305766176437, -7.4361899359832, -15.8954215629556, 79.6186327084103,
    -127.457278992502, 63.7349456687829);
const mat4 kMomentQ8OddInv = mat4(
    -0.00482399708502382, -0.423201508674231, 0.0348312382605129, 1.67179208266592,
    -0.0233402218644408, -0.832829097046478, 0.0193406040499625, 1.21021509068975,
    -0.010888537031885, -0.926393772997063, -0.11723394414779, 0.983723301818275,
    -0.0308713357806732, -0.937989172670245, -0.218033377677099, 0.845991731322996);
const mat4 kMomentQ8EvenInv = mat4(
    -0.976220278891035, -0.456139260269401, -0.0504335521016742, 0.000838800390651085,
    -1.04828341778299, -0.229726640510149, 0.0259608334616091, -0.00133632693205861,
    -1.03115268628604, -0.077844420809897, 0.00443408851014257, -0.0103744938457406,
    -0.996038443434636, 0.0175438624416783, -0.0361414253243963, -0.00317839994022725);
const vec4 kMomentQ8EvenOffset =
    vec4(0.972481993925964, 1.0, 0.999179192513328, 0.991778293073131);
void momentQuantize8(vec4 odd, vec4 even, out vec4 qOdd, out vec4 qEven) {
    qOdd = odd * kMomentQ8Odd + vec4(0.5);
    qEven = even * kMomentQ8Even + kMomentQ8EvenOffset;
}
void momentDequantize8(vec4 qOdd, vec4 qEven, out vec4 odd, out vec4 even) {
    odd = (qOdd - vec4(0.5)) * kMomentQ8OddInv;
    even = (qEven - kMomentQ8EvenOffset) * kMomentQ8EvenInv;
}
