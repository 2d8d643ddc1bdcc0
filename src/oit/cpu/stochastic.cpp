#include "oit/cpu/stochastic.h"

#include "base/error.h"

#include <cmath>
#include <unordered_set>

namespace veil::oit::cpu {

namespace {

double binomial(int n, int k) {
    double c = 1.0;
    for (int i = 1; i <= k; ++i)
        c = c * (n - k + i) / i;
    return c;
}

// All masks of `r` bits out of `n`, in increasing order (Gosper's hack).
void appendAllMasks(int n, int r, std::vector<std::uint32_t>& out) {
    if (r == 0) {
        out.push_back(0u);
        return;
    }
    const std::uint64_t limit = std::uint64_t{1} << n;
    std::uint64_t m = (std::uint64_t{1} << r) - 1;
    while (m < limit) {
        out.push_back(static_cast<std::uint32_t>(m));
        const std::uint64_t c = m & (~m + 1);
        const std::uint64_t rr = m + c;
        m = (((rr ^ m) >> 2) / c) | rr;
    }
}

// `count` distinct masks of `r` bits out of `n`, each a uniform random r-subset (partial
// Fisher-Yates), from a fixed-seed hash stream.
void appendSampledMasks(int n, int r, int count, std::vector<std::uint32_t>& out) {
    std::unordered_set<std::uint32_t> seen;
    std::uint32_t state = 0x5EED0000u ^ static_cast<std::uint32_t>(n * 64 + r);
    while (static_cast<int>(seen.size()) < count) {
        int pos[kStochasticMaxMaskBits];
        for (int i = 0; i < n; ++i)
            pos[i] = i;
        std::uint32_t mask = 0;
        for (int i = 0; i < r; ++i) {
            state = stochasticHash(state + 0x9E3779B9u);
            const int j = i + static_cast<int>(state % static_cast<std::uint32_t>(n - i));
            std::swap(pos[i], pos[j]);
            mask |= 1u << pos[i];
        }
        if (seen.insert(mask).second) out.push_back(mask);
    }
}

} // namespace

bool StochasticMaskTable::complete(int r) const {
    return static_cast<double>(count[static_cast<std::size_t>(r)]) == binomial(bits, r);
}

StochasticMaskTable buildStochasticMaskTable(int bits) {
    VEIL_CHECK(bits >= 1 && bits <= kStochasticMaxMaskBits,
               "stochastic transparency: {} mask bits requested, supported 1..{}", bits,
               kStochasticMaxMaskBits);
    StochasticMaskTable table;
    table.bits = bits;
    for (int r = 0; r <= bits; ++r) {
        const auto ri = static_cast<std::size_t>(r);
        table.offset[ri] = static_cast<std::uint32_t>(table.masks.size());
        if (binomial(bits, r) <= kStochasticMasksPerCount)
            appendAllMasks(bits, r, table.masks);
        else
            appendSampledMasks(bits, r, kStochasticMasksPerCount, table.masks);
        table.count[ri] = static_cast<std::uint32_t>(table.masks.size()) - table.offset[ri];
    }
    return table;
}

std::uint32_t stochasticHash(std::uint32_t v) {
    const std::uint32_t state = v * 747796405u + 2891336453u;
    const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

std::uint32_t stochasticFragmentHash(std::uint32_t x, std::uint32_t y, std::uint32_t depthBits,
                                     std::uint32_t seed, std::uint32_t group) {
    std::uint32_t h = stochasticHash(seed + stochasticHash(group));
    h = stochasticHash(h + ((depthBits + 0x80u) >> 8u));
    h = stochasticHash(h + y);
    return stochasticHash(h + x);
}

int stochasticCoverageCount(float alpha, int bits, std::uint32_t hash) {
    // xi from the top 24 bits, exact in float.
    const float xi = static_cast<float>(stochasticHash(hash) >> 8u) * (1.0f / 16777216.0f);
    const float a = std::fmin(std::fmax(alpha, 0.0f), 1.0f);
    const int r = static_cast<int>(std::floor(a * static_cast<float>(bits) + xi));
    return r > bits ? bits : r;
}

std::uint32_t stochasticPickMask(const StochasticMaskTable& table, int r, std::uint32_t hash) {
    const auto ri = static_cast<std::size_t>(r);
    const std::uint32_t index = stochasticHash(stochasticHash(hash)) % table.count[ri];
    return table.masks[table.offset[ri] + index];
}

std::array<double, 3> stochasticExactComposite(const std::vector<StochasticFragment>& fragments,
                                               const double background[3]) {
    std::array<double, 3> c{0, 0, 0};
    double t = 1.0;
    for (const auto& f : fragments) {
        for (int k = 0; k < 3; ++k)
            c[static_cast<std::size_t>(k)] += t * f.alpha * f.color[k];
        t *= 1.0 - f.alpha;
    }
    for (int k = 0; k < 3; ++k)
        c[static_cast<std::size_t>(k)] += t * background[k];
    return c;
}

StochasticStats simulateStochasticPixel(const std::vector<StochasticFragment>& fragments,
                                        const double background[3], StochasticVariant variant,
                                        int samples, int passes, int trials, std::uint32_t seed) {
    VEIL_CHECK(samples >= 1 && samples <= kStochasticMaxMaskBits && passes >= 1 && trials >= 1,
               "simulateStochasticPixel: bad sample count {} / passes {} / trials {}", samples,
               passes, trials);
    const int total = samples * passes;
    const bool grouped = total <= kStochasticMaxMaskBits; // one mask split across passes
    const int bits = grouped ? total : samples;
    const int groups = grouped ? 1 : passes;
    const StochasticMaskTable table = buildStochasticMaskTable(bits);
    const int n = static_cast<int>(fragments.size());
    const std::array<double, 3> exact = stochasticExactComposite(fragments, background);
    double transmit = 1.0;
    for (const auto& f : fragments)
        transmit *= 1.0 - f.alpha;
    const double alphaTotal = 1.0 - transmit; // [Enderton11 Eq. 5]

    StochasticStats stats;
    std::vector<int> winner(static_cast<std::size_t>(total));
    for (int trial = 0; trial < trials; ++trial) {
        // Fragments listed front to back: the winner of a sample is the first one covering it.
        for (int g = 0; g < groups; ++g) {
            std::vector<std::uint32_t> masks(static_cast<std::size_t>(n));
            for (int i = 0; i < n; ++i) {
                const std::uint32_t h =
                    stochasticFragmentHash(static_cast<std::uint32_t>(trial), 0u,
                                           0x3f000000u + 0x1000u * static_cast<std::uint32_t>(i),
                                           seed, static_cast<std::uint32_t>(g));
                const auto& f = fragments[static_cast<std::size_t>(i)];
                const int r = stochasticCoverageCount(static_cast<float>(f.alpha), bits, h);
                masks[static_cast<std::size_t>(i)] = stochasticPickMask(table, r, h);
            }
            for (int s = 0; s < bits; ++s) {
                int w = n; // background
                for (int i = 0; i < n && w == n; ++i)
                    if ((masks[static_cast<std::size_t>(i)] >> s) & 1u) w = i;
                winner[static_cast<std::size_t>(g * bits + s)] = w;
            }
        }
        double b[3] = {0, 0, 0}, b1 = 0, u[3] = {0, 0, 0}, u1 = 0, empty = 0;
        for (int w : winner) {
            if (w == n) {
                empty += 1.0;
            } else {
                b1 += 1.0;
                for (int k = 0; k < 3; ++k)
                    b[k] += fragments[static_cast<std::size_t>(w)].color[k];
            }
            // [Enderton11 Eq. 4/6]: fragments at or in front of the winner see this sample.
            for (int i = 0; i < n && i <= w; ++i) {
                const auto& f = fragments[static_cast<std::size_t>(i)];
                u1 += f.alpha;
                for (int k = 0; k < 3; ++k)
                    u[k] += f.alpha * f.color[k];
            }
        }
        for (int k = 0; k < 3; ++k) {
            double v = 0.0;
            switch (variant) {
            case StochasticVariant::Basic: // [Enderton11 sec. 3.1]
                v = (b[k] + empty * background[k]) / total;
                break;
            case StochasticVariant::AlphaCorrected: // [Enderton11 sec. 4.1], A
                v = (b1 > 0 ? alphaTotal * b[k] / b1 : 0.0) + transmit * background[k];
                break;
            case StochasticVariant::DepthBased: // [Enderton11 sec. 4.2], D
                v = (u1 > 0 ? alphaTotal * u[k] / u1 : 0.0) + transmit * background[k];
                break;
            }
            const double e = v - exact[static_cast<std::size_t>(k)];
            stats.mean[k] += v;
            stats.rms[k] += e * e;
        }
    }
    for (int k = 0; k < 3; ++k) {
        stats.mean[k] /= trials;
        stats.rms[k] = std::sqrt(stats.rms[k] / trials);
        stats.exact[k] = exact[static_cast<std::size_t>(k)];
    }
    return stats;
}

} // namespace veil::oit::cpu
