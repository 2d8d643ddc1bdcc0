// The `volume` technique's classification ([Eisemann06 sec. 3.2],
// shaders/shadows/volume/classify.comp through shadows::runClassify) on synthetic slice maps
// against a CPU evaluation of the same rules written directly from the paper's definitions (every
// column of the footprint, every slice at or behind the caster), with casters whose footprints span
// from one column to the whole 256^2 grid (64 reduce groups) and every combination of the three
// switches. Tolerance: none. The light views are axis-aligned with power-of-two scales, so every
// GPU operation before the decisions is exact in float and the clamp depth is one correctly rounded
// add: the decisions and clamp depths must be equal bit for bit.
#include "gl_fixture.h"

#include "gpu/shader.h"
#include "shaders/common/bindings.h"
#include "shadows/views.h"
#include "shadows/volume/classify.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace veil::test {
namespace {

class ShadowVolumeClassifyTest : public GlTest {};

constexpr int kGrid = 256, kSlices = 128, kWords = kSlices / 32, kSlots = 3;

struct Box {
    glm::vec3 lo, hi;
};

// One caster and slot by the rules of classify.comp's header, column by column and slice by
// slice. View 0: uv = (x, y); view 1: uv = (x, y) / 2 + 1/4; depth = z for both.
float cpuDecision(const Box& b, int view, bool unbounded, const std::vector<float>& occluders,
                  const std::vector<std::uint32_t>& receivers, int slot, glm::bvec3 on) {
    if (view < 0) return 0.0f;
    const float scale = view == 0 ? 1.0f : 0.5f, offset = view == 0 ? 0.0f : 0.25f;
    const glm::vec2 uvLo = glm::vec2(b.lo) * scale + offset,
                    uvHi = glm::vec2(b.hi) * scale + offset;
    const float dLo = b.lo.z, dHi = b.hi.z;
    glm::ivec2 c0 = glm::ivec2(glm::floor(uvLo * float(kGrid))) - 1;
    glm::ivec2 c1 = glm::ivec2(glm::floor(uvHi * float(kGrid))) + 1;
    if (c1.x < 0 || c1.y < 0 || c0.x >= kGrid || c0.y >= kGrid)
        return on.y && !unbounded ? -1.0f : 0.0f; // outside the light's view
    c0 = glm::max(c0, glm::ivec2(0));
    c1 = glm::min(c1, glm::ivec2(kGrid - 1));
    const int s0 = std::clamp(int(std::floor(dLo * float(kSlices))), 0, kSlices - 1);
    float farthest = 0.0f; // every column's occluder nearer than the caster?
    int last = -1;         // the farthest receiver slice at or behind the caster's nearest
    for (int y = c0.y; y <= c1.y; ++y)
        for (int x = c0.x; x <= c1.x; ++x) {
            const int g = (slot * kGrid + y) * kGrid + x;
            farthest = std::max(farthest, std::max(occluders[g], 0.0f));
            for (int s = s0; s < kSlices; ++s)
                if (receivers[g * kWords + s / 32] >> (s % 32) & 1u) last = std::max(last, s);
        }
    if (on.x && farthest < dLo) return -1.0f;
    if (unbounded || !(on.y || on.z)) return 0.0f;
    if (last < 0) return on.y ? -1.0f : 0.0f;
    return on.z ? std::max(dHi, float(last + 2) / float(kSlices)) + 1e-4f : 0.0f;
}

TEST_F(ShadowVolumeClassifyTest, DecisionsMatchCpuRulesOnLargeFootprints) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    // Casters: a floor over the whole grid (and beyond it), a slab over most of it, one outside
    // both views, small and mid-sized boxes; lo/hi on a 1/1024 lattice (exact in float).
    auto q = [](float v) { return std::round(v * 1024.0f) / 1024.0f; };
    std::vector<Box> boxes = {{{-0.1f, -0.1f, 0.95f}, {1.1f, 1.1f, 0.96f}},
                              {{0.05f, 0.1f, 0.3f}, {0.9f, 0.95f, 0.32f}},
                              {{0.02f, 0.6f, 0.5f}, {0.45f, 0.98f, 0.55f}},
                              {{2.0f, 2.0f, 0.2f}, {3.0f, 3.0f, 0.3f}}};
    for (int i = 0; i < 60; ++i) {
        const float size = i % 3 == 0 ? 0.4f : 0.05f;
        const glm::vec3 lo(u(rng) * 1.3f - 0.2f, u(rng) * 1.3f - 0.2f, u(rng) * 0.9f);
        boxes.push_back({lo, lo + glm::vec3(u(rng) * size, u(rng) * size, u(rng) * 0.1f)});
    }
    std::vector<glm::vec4> bounds;
    for (Box& b : boxes) {
        b.lo = glm::vec3(q(b.lo.x), q(b.lo.y), q(b.lo.z));
        b.hi = glm::vec3(q(b.hi.x), q(b.hi.y), q(b.hi.z));
        bounds.emplace_back(b.lo, 0.0f);
        bounds.emplace_back(b.hi, 0.0f);
    }
    // Occluders: near (0.2-0.25) but at one column in 400 of the right half (anywhere).
    // Receivers: two thirds of the columns with 3 near slices (< 64), one in 300 with a far
    // one; the top row's column 250 holds the grid's farthest occluder (0.97) and a far
    // receiver (slice 126) alone, so the floor's decisions depend on its last reduce group.
    std::vector<float> occluders(kSlots * kGrid * kGrid);
    std::vector<std::uint32_t> receivers(VEIL_MAX_LIGHTS + kSlots * kGrid * kGrid * kWords, 0u);
    receivers[1] = 1u; // slot 1 is unbounded
    auto setReceiver = [&](int g, int slice) {
        receivers[VEIL_MAX_LIGHTS + g * kWords + slice / 32] |= 1u << (slice % 32);
    };
    for (int s = 0; s < kSlots; ++s)
        for (int y = 0; y < kGrid; ++y)
            for (int x = 0; x < kGrid; ++x) {
                const int g = (s * kGrid + y) * kGrid + x;
                occluders[g] =
                    x >= kGrid / 2 && rng() % 400 == 0 ? 0.95f * u(rng) : 0.2f + 0.05f * u(rng);
                if (rng() % 3 != 0)
                    for (int k = 0; k < 3; ++k)
                        setReceiver(g, int(rng() % 64));
                if (rng() % 300 == 0) setReceiver(g, 64 + int(rng() % 60));
                if (x == 250 && y == kGrid - 1) {
                    occluders[g] = 0.97f;
                    setReceiver(g, 126);
                }
            }
    const std::vector<std::uint32_t> words(receivers.begin() + VEIL_MAX_LIGHTS, receivers.end());

    shadows::ShadowsBlock block{};
    block.views[0].worldToTexture = glm::mat4(1.0f);
    block.views[1].worldToTexture = glm::mat4(1.0f);
    block.views[1].worldToTexture[0][0] = block.views[1].worldToTexture[1][1] = 0.5f;
    block.views[1].worldToTexture[3] = glm::vec4(0.25f, 0.25f, 0.0f, 1.0f);
    for (int v = 0; v < 2; ++v) {
        block.views[v].worldToView = glm::mat4(1.0f);
        block.views[v].worldToView[2][2] = -1.0f; // depth along -z = world z
        block.views[v].depthRange = {0.0f, 1.0f, 1.0f, 1.0f};
    }
    const int slotView[kSlots] = {0, 1, -1};

    gpu::Buffer ubo, rb, ob, bb, cb, fb;
    ubo.setStorage(sizeof block, &block);
    rb.setStorage(std::span<const std::uint32_t>(receivers));
    ob.setStorage(std::span<const float>(occluders));
    bb.setStorage(std::span<const glm::vec4>(bounds));
    const int entries = int(boxes.size()) * kSlots;
    cb.setStorage(entries * 4, nullptr);
    fb.setStorage(entries * 8, nullptr);
    ubo.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_SHADOWS);
    rb.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_RECEIVERS);
    ob.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_OCCLUDERS);
    bb.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_BOUNDS);
    cb.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_VOLUME_CASTERS);

    gpu::Program p(gpu::ProgramDesc::compute("shadows/volume/classify.comp"));
    p.use();
    for (int s = 0; s < VEIL_MAX_LIGHTS; ++s)
        p.set(fmt::format("uSlotView[{}]", s).c_str(), s < kSlots ? slotView[s] : -1);
    p.set("uGrid", kGrid).set("uSlices", kSlices).set("casterCount", int(boxes.size()));
    p.set("slotCount", kSlots);
    int culled = 0, clamped = 0, casterCulled = 0;
    for (int mask = 0; mask < 8; ++mask) {
        const glm::bvec3 on(mask & 1, mask & 2, mask & 4);
        glUniform3i(p.uniformLocation("uEnable"), on.x, on.y, on.z);
        const float poison = 7.0f; // every entry must be written
        glClearNamedBufferData(cb.id(), GL_R32F, GL_RED, GL_FLOAT, &poison);
        shadows::runClassify(p, fb, entries, kGrid);
        std::vector<float> got(entries);
        glGetNamedBufferSubData(cb.id(), 0, entries * 4, got.data());
        VEIL_EXPECT_NO_GL_ERROR();
        for (int i = 0; i < entries; ++i) {
            const int caster = i / kSlots, slot = i % kSlots;
            const float want = cpuDecision(boxes[caster], slotView[slot], receivers[slot] != 0u,
                                           occluders, words, slot, on);
            EXPECT_EQ(got[i], want) << "caster " << caster << " slot " << slot << " mask " << mask;
            if (mask == 7) {
                culled += want < 0;
                clamped += want > 0;
            }
            if (mask == 1) casterCulled += want < 0;
        }
    }
    // The scene exercises every outcome (else the comparison proves little).
    EXPECT_GE(casterCulled, 3);
    EXPECT_GE(culled, casterCulled + 3);
    EXPECT_GE(clamped, 10);
}

} // namespace
} // namespace veil::test
