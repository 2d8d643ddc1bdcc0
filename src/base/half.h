// IEEE 754 binary16 ("half") from float, rounded to nearest with ties to even. The EXR writer
// converts here rather than trusting a library or driver: a round-toward-zero conversion biases
// every value down by half a step on average (-2.4e-4 at 0.7, measured on llvmpipe's RGBA16F
// targets).
#pragma once

#include <bit>
#include <cstdint>

namespace veil {

inline std::uint16_t floatToHalf(float value) {
    const std::uint32_t f = std::bit_cast<std::uint32_t>(value);
    const std::uint32_t sign = (f >> 16) & 0x8000u;
    const std::uint32_t absBits = f & 0x7fffffffu;
    if (absBits >= 0x7f800000u) // Inf stays Inf; NaN stays a (quiet) NaN
        return static_cast<std::uint16_t>(sign | 0x7c00u | (absBits > 0x7f800000u ? 0x200u : 0u));
    // 65520 = 65504 + half a step rounds up to Inf.
    if (absBits >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);
    const int exponent = static_cast<int>(absBits >> 23) - 127;
    std::uint32_t mantissa = (absBits & 0x7fffffu) | 0x800000u; // with the implicit 1
    // Bits of the 24-bit significand dropped: 13 for normal halves, more for subnormals.
    int shift = 13;
    std::uint32_t halfExponent = 0;
    if (exponent < -14) {
        shift = 13 + (-14 - exponent);
        if (shift > 24) return static_cast<std::uint16_t>(sign); // below half the smallest
    } else {
        halfExponent = static_cast<std::uint32_t>(exponent + 15);
        mantissa &= 0x7fffffu;
    }
    const std::uint32_t kept = mantissa >> shift;
    const std::uint32_t rest = mantissa & ((1u << shift) - 1u);
    const std::uint32_t halfway = 1u << (shift - 1);
    std::uint32_t bits = (halfExponent << 10) + kept;
    // A carry out of the mantissa correctly increments the exponent (or makes a subnormal
    // normal).
    if (rest > halfway || (rest == halfway && (kept & 1u))) ++bits;
    return static_cast<std::uint16_t>(sign | bits);
}

inline float halfToFloat(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16;
    const std::uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
    if (exponent == 0) { // zero or subnormal: mantissa * 2^-24
        const float v = static_cast<float>(mantissa) * (1.0f / 16777216.0f);
        return sign ? -v : v;
    }
    if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));
    return std::bit_cast<float>(sign | ((exponent + 112) << 23) | (mantissa << 13));
}

} // namespace veil
