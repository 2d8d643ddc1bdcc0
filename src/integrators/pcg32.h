// PCG32 (XSH RR output of a 64-bit LCG) [ONeill14]: the path tracer's random numbers, one
// stream per (seed, pixel, sample) so results do not depend on threads or scheduling.
#pragma once

#include <cstdint>

namespace veil::volume {

class Pcg32 {
public:
    Pcg32(std::uint64_t state, std::uint64_t stream) : inc_((stream << 1u) | 1u) {
        next();
        state_ += state;
        next();
    }
    std::uint32_t next() {
        const std::uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const auto shifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<std::uint32_t>(old >> 59u);
        return (shifted >> rot) | (shifted << ((~rot + 1u) & 31u));
    }
    // Uniform in [0, 1) with 53 random bits.
    double uniform() {
        const std::uint64_t hi = next() >> 5, lo = next() >> 6; // 27 + 26 bits
        return double((hi << 26) | lo) * 0x1.0p-53;
    }

private:
    std::uint64_t state_ = 0;
    std::uint64_t inc_;
};

// SplitMix64's finalizer: decorrelates the stream keys.
inline std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

} // namespace veil::volume
