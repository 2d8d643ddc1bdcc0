// `reference`: exact per-pixel sorted compositing with per-pixel linked lists (the ground
// truth the approximate techniques are measured against).
//
// Properties (declared in registerReference; defaults in brackets):
//   initial_nodes_per_pixel [4]    starting node-pool size = this * width * height (min 4096)
//   max_pool_mib            [1024] cap on the node pool; also capped by the driver's
//                                  GL_MAX_SHADER_STORAGE_BLOCK_SIZE. Past it: veil::Error.
//   max_fragments_per_pixel [256] local array of the resolve (OIT_REF_MAX_FRAGMENTS), 1..512;
//                                 deeper pixels keep their nearest ones, the rest are counted
//                                 (ReferenceStats::pixelOverflowFragments, with the deepest
//                                 list in maxListLength) and warned about once. 256 holds
//                                 default.json's deepest pixel at 1920x1080 (217 fragments;
//                                 128 dropped 240,115 there); each doubling costs the resolve
//                                 time (H200, default.json 1080p: 3.25 ms at 128, 5.74 at
//                                 512); NVIDIA's compiler refuses 2048 (bench/RESULTS.md).
//   pool_overflow           [error] past the cap: "error" (veil::Error, `veil render`) or
//                                  "drop" (the pool stays at the cap, the fragments that do
//                                  not fit are left out and counted in stats().
//                                  pool_dropped_fragments; the viewer's default)
// Storage: an r32ui head-pointer image, an r32f image of each pixel's list length written by
// the resolve (the frame resource oit.reference.fragments_per_pixel: surface fragments plus,
// with fog, one node per fog segment; the viewer's heat map), a node pool SSBO of 32-byte nodes
// (premultiplied radiance rgb, view depth, modulation rgb = 1 - a + a T [McGuire16 Eq. 2], next
// index) and a counter SSBO {nodes requested, fragments dropped by the resolve}. Pool overflow:
// after the last geometry pass repeatAccumulation() reads the counter back; if more nodes were
// requested than the pool holds, the pool grows to the next power of two and the frame re-runs the
// transparent passes (grow-and-repeat: the pool ends sized from the frame's actual fragment count,
// rounded up to a power of two). Fog: fogSegments() is true, so the frame marches the fog per
// segment between the sorted surfaces of each pixel (oitNextSurfaceDepth() in emit.glsl) and
// appends one node per segment.
#pragma once

#include "oit/technique.h"

#include <cstdint>

namespace veil::oit {

struct ReferenceLimits {
    std::uint64_t initialNodesPerPixel = 4;
    std::uint64_t maxPoolBytes = std::uint64_t(1) << 30;
    int maxFragmentsPerPixel = 256; // ReferenceTechnique::kDefaultMaxFragmentsPerPixel
    bool dropPastCap = false;       // pool_overflow = "drop"
};

struct ReferenceStats {
    std::uint64_t fragments = 0;              // fragments stored in the last frame
    std::uint64_t poolNodes = 0;              // node-pool capacity now
    int poolGrowths = 0;                      // times the pool grew (lifetime of the technique)
    int accumulationRepeats = 0;              // extra accumulations in the last frame
    std::uint64_t pixelOverflowFragments = 0; // dropped by the resolve's local array, last frame
    std::uint64_t maxListLength = 0;          // deepest per-pixel list of the last frame
    std::uint64_t poolDroppedFragments = 0;   // did not fit the capped pool, last frame ("drop")
};

class ReferenceTechnique final : public Technique {
public:
    static constexpr int kDefaultMaxFragmentsPerPixel = 256;
    static constexpr std::size_t kNodeBytes = 32;
    static constexpr const char* kFragmentsPerPixel = "oit.reference.fragments_per_pixel";

    ReferenceTechnique(gpu::ProgramManager& programs, const ReferenceLimits& limits);
    std::string name() const override { return "reference"; }
    std::filesystem::path emitInclude() const override { return "oit/reference/emit.glsl"; }
    bool fogSegments() const override { return true; }
    void resize(const pass::Context& targets) override;
    void beginAccumulate(int pass, const pass::Context& targets,
                         const gpu::Program& program) override;
    void prepareProgram(int pass, const gpu::Program& program) const override;
    void endAccumulate(int pass) override;
    bool repeatAccumulation() override;
    void resolve(const pass::Context& targets) override;
    std::size_t bytesPerPixel() const override;

    std::vector<Resource> resources() const override {
        return {{kFragmentsPerPixel, [this] { return &fragmentCounts_; }, true}};
    }

    const ReferenceStats& referenceStats() const { return stats_; }
    nlohmann::json stats() const override;

private:
    void allocatePool(std::uint64_t nodes);

    gpu::ProgramManager& programs_;
    gpu::ProgramHandle resolveProgram_;
    ReferenceLimits limits_;
    std::uint64_t maxPoolNodes_ = 0;
    int width_ = 0, height_ = 0;
    gpu::Texture heads_{gpu::NoCreate}, fragmentCounts_{gpu::NoCreate};
    gpu::Buffer nodes_{gpu::NoCreate}, counters_{gpu::NoCreate};
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
    ReferenceStats stats_;
    int repeatsThisFrame_ = 0;
    bool warnedOverflow_ = false;
};

void registerReference(Registry& registry);

} // namespace veil::oit
