// CPU exact compositing (src/oit/cpu/composite.h) against the worked examples of [Enderton11]
// (Enderton et al., Stochastic Transparency, section 3.1), in double precision.
#include "base/error.h"
#include "oit/cpu/composite.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace veil::test {

using oit::cpu::compositeInOrder;
using oit::cpu::compositeSorted;
using oit::cpu::Fragment;
using oit::cpu::makeFragment;

TEST(OitCpuCompositeTest, Example1RedOverGreenOverBlueBackground) {
    // [Enderton11 Example 1]: red (alpha 0.45) in front of green (alpha 0.45), pure blue
    // background: c = a0 c0 + (1-a0) a1 c1 + (1-a0)(1-a1) cb = (0.45, 0.2475, 0.3025). Submitted
    // back to front to show the sort does its job.
    const std::vector<Fragment> frags = {makeFragment(2.0, {0, 1, 0}, 0.45),
                                         makeFragment(1.0, {1, 0, 0}, 0.45)};
    const glm::dvec3 c = compositeSorted(frags, {0, 0, 1});
    EXPECT_NEAR(c.r, 0.45, 1e-12);
    EXPECT_NEAR(c.g, 0.2475, 1e-12);
    EXPECT_NEAR(c.b, 0.3025, 1e-12);
}

TEST(OitCpuCompositeTest, Example1NeedsABlueBackgroundNotABlueLayer) {
    // The paper's value needs the blue to be the (opaque) background. A third blue layer of
    // alpha 0.45 over black gives 0.45 * 0.55^2 in blue instead: guard against mixing them up.
    const std::vector<Fragment> frags = {makeFragment(1.0, {1, 0, 0}, 0.45),
                                         makeFragment(2.0, {0, 1, 0}, 0.45),
                                         makeFragment(3.0, {0, 0, 1}, 0.45)};
    const glm::dvec3 c = compositeSorted(frags, {0, 0, 0});
    EXPECT_NEAR(c.b, 0.45 * 0.55 * 0.55, 1e-12);
    EXPECT_GT(std::abs(c.b - 0.3025), 0.1);
}

TEST(OitCpuCompositeTest, Example2FourWhiteSmokeBlobs) {
    // [Enderton11 Example 2]: N = 4 white fragments of alpha 1/N over a 25% grey background:
    // c = (1-a)^N cb + sum_{i<N} (1-a)^i a cf = 0.75^4 * 0.25 + (1 - 0.75^4) = 0.7626953125.
    const int n = 4;
    std::vector<Fragment> frags;
    for (int i = 0; i < n; ++i)
        frags.push_back(makeFragment(i, glm::dvec3(1.0), 1.0 / n));
    const glm::dvec3 c = compositeSorted(frags, glm::dvec3(0.25));
    const double expected = std::pow(0.75, 4) * 0.25 + (1.0 - std::pow(0.75, 4));
    EXPECT_DOUBLE_EQ(expected, 0.7626953125);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(c[k], 0.7626953125, 1e-12);
}

TEST(OitCpuCompositeTest, SortedCompositeIsOrderIndependent) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Fragment> frags;
    for (int i = 0; i < 12; ++i)
        frags.push_back(makeFragment(u(rng) * 10.0, {u(rng), u(rng), u(rng)}, u(rng),
                                     {u(rng), u(rng), u(rng)}));
    const glm::dvec3 bg(0.2, 0.3, 0.4);
    const glm::dvec3 ref = compositeSorted(frags, bg);
    bool anyOrderDiffers = false;
    for (int trial = 0; trial < 20; ++trial) {
        std::shuffle(frags.begin(), frags.end(), rng);
        const glm::dvec3 c = compositeSorted(frags, bg);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(c[k], ref[k], 1e-12);
        // Without the sort the result depends on the order (so the test above can fail).
        const glm::dvec3 unsorted = compositeInOrder(frags, bg);
        if (glm::length(unsorted - ref) > 1e-3) anyOrderDiffers = true;
    }
    EXPECT_TRUE(anyOrderDiffers);
}

TEST(OitCpuCompositeTest, ColoredTransmissionModulatesPerChannel) {
    // One clear red-glass layer (alpha 1, T = (1, 0, 0), no reflection) over white: (1, 0, 0).
    const glm::dvec3 c =
        compositeSorted({makeFragment(1.0, glm::dvec3(0.0), 1.0, {1, 0, 0})}, glm::dvec3(1.0));
    EXPECT_NEAR(c.r, 1.0, 1e-12);
    EXPECT_NEAR(c.g, 0.0, 1e-12);
    EXPECT_NEAR(c.b, 0.0, 1e-12);
    EXPECT_NEAR(oit::cpu::netModulation({makeFragment(0, {}, 0.5, {0.5, 0.5, 0.5})}).g, 0.75,
                1e-12);
}

TEST(OitCpuCompositeTest, StableForEqualDepths) {
    // Equal depths keep the given order: the first listed is in front.
    const std::vector<Fragment> frags = {makeFragment(1.0, {1, 0, 0}, 1.0),
                                         makeFragment(1.0, {0, 1, 0}, 1.0)};
    EXPECT_NEAR(compositeSorted(frags, {}).r, 1.0, 1e-12);
}

TEST(OitCpuCompositeTest, BadInputIsAnError) {
    EXPECT_THROW(makeFragment(0, {1, 1, 1}, 1.5), Error);
    EXPECT_THROW(makeFragment(0, {1, 1, 1}, 0.5, {2, 0, 0}), Error);
    EXPECT_THROW(makeFragment(NAN, {1, 1, 1}, 0.5), Error);
}

} // namespace veil::test
