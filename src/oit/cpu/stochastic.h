// CPU side of stochastic transparency [Enderton11], no GL:
//  - the S-choose-R mask table ([Enderton11 sec. 3.1] stratified masks, section 5 "precomputed
//    lookup table ... indexed by alpha in one dimension and a pseudorandom seed in the other"),
//    uploaded as an SSBO by src/oit/stochastic and read by shaders/oit/stochastic/emit.glsl;
//  - the per-fragment hash and coverage-count rule that emit.glsl mirrors bit for bit;
//  - a double-precision Monte Carlo simulation of the three estimators of a single pixel
//    (basic B, alpha-corrected A, depth-based D of [Enderton11 sec. 4]) with samples at the pixel
//    centre, used by the tests to derive the expected RMS error per sample count.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace veil::oit::cpu {

// Most mask bits per fragment (gl_SampleMask[0] holds 32 samples).
inline constexpr int kStochasticMaxMaskBits = 32;
// Masks stored per coverage count R. C(16, 8) = 12870 fits, so for N <= 16 bits the table
// holds every mask ([Enderton11 sec. 5]: "for 16 samples, it is at most 12,870"); beyond that it
// holds this many distinct masks drawn uniformly at random.
inline constexpr int kStochasticMasksPerCount = 16384;

// Masks of exactly R set bits out of N, for R = 0..N, concatenated.
struct StochasticMaskTable {
    int bits = 0;                                                   // N
    std::array<std::uint32_t, kStochasticMaxMaskBits + 1> offset{}; // first mask of count R
    std::array<std::uint32_t, kStochasticMaxMaskBits + 1> count{};  // masks with R bits
    std::vector<std::uint32_t> masks;
    // Whether the masks of count R are all C(N, R) of them.
    bool complete(int r) const;
};

// Builds the table for N = `bits` in 1..32 (throws veil::Error otherwise). Deterministic:
// the sampled rows (N > 16) come from a fixed-seed generator.
StochasticMaskTable buildStochasticMaskTable(int bits);

// PCG-style integer hash (the output permutation of PCG32, [ONeill14]). Mirrored in
// shaders/oit/stochastic/emit.glsl: change both together.
std::uint32_t stochasticHash(std::uint32_t v);
// Per-fragment hash of (pixel, depth, seed, mask group): [Enderton11 sec. 6] "include pixel (x,y)
// in the seed ... seeding by fragment z is effective for still images". depthBits are the
// float bits of the window depth; they are rounded to 15 mantissa bits here (emit.glsl says
// why the primitive id is not used).
std::uint32_t stochasticFragmentHash(std::uint32_t x, std::uint32_t y, std::uint32_t depthBits,
                                     std::uint32_t seed, std::uint32_t group);
// [Enderton11 sec. 3.1]: R = floor(alpha * N + xi), xi uniform in [0,1) taken from the hash.
int stochasticCoverageCount(float alpha, int bits, std::uint32_t hash);
// The mask a fragment with this hash and count R uses (index = second hash mod count).
std::uint32_t stochasticPickMask(const StochasticMaskTable& table, int r, std::uint32_t hash);

// ---- single-pixel simulation (samples at the pixel centre, [Enderton11 secs. 3.1-3.4]) ----------

struct StochasticFragment {
    double color[3];
    double alpha;
};

enum class StochasticVariant { Basic, AlphaCorrected, DepthBased };

struct StochasticStats {
    double mean[3] = {0, 0, 0};
    double rms[3] = {0, 0, 0}; // root mean square error against the exact composite
    double exact[3] = {0, 0, 0};
};

// Exact "over" composite [Enderton11 Eq. 1/2] of fragments ordered front to back over `background`.
std::array<double, 3> stochasticExactComposite(const std::vector<StochasticFragment>& fragments,
                                               const double background[3]);

// Simulates `trials` pixels with `samples` samples per pass and `passes` passes, masks from
// the table of samples * passes bits when that is <= 32 (one mask split across passes, [Enderton11
// footnote 3]) and independent per-pass masks otherwise, as the GL technique does.
StochasticStats simulateStochasticPixel(const std::vector<StochasticFragment>& fragments,
                                        const double background[3], StochasticVariant variant,
                                        int samples, int passes, int trials, std::uint32_t seed);

} // namespace veil::oit::cpu
