#include "oit/reference/reference.h"

#include "base/error.h"
#include "base/log.h"

#include "shaders/common/bindings.h"

#include <algorithm>
#include <array>

namespace veil::oit {

namespace {
constexpr GLuint kEndOfList = 0xFFFFFFFFu;

std::uint64_t nextPowerOfTwo(std::uint64_t v) {
    std::uint64_t p = 1;
    while (p < v)
        p <<= 1;
    return p;
}

double mib(std::uint64_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }
} // namespace

ReferenceTechnique::ReferenceTechnique(gpu::ProgramManager& programs, const ReferenceLimits& limits)
    : programs_(programs), limits_(limits) {
    resolveProgram_ = programs_.add(gpu::ProgramDesc::compute(
        "oit/reference/resolve.comp",
        {fmt::format("OIT_REF_MAX_FRAGMENTS {}", limits_.maxFragmentsPerPixel)}));
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    std::uint64_t capBytes = limits_.maxPoolBytes;
    if (maxBlock > 0)
        capBytes = std::min<std::uint64_t>(capBytes, static_cast<std::uint64_t>(maxBlock));
    // Node indices are 32-bit with 0xFFFFFFFF as the list end.
    maxPoolNodes_ = std::min<std::uint64_t>(capBytes / kNodeBytes, kEndOfList - 1);
    counters_ = gpu::Buffer();
    counters_.setStorage(4 * sizeof(GLuint), nullptr);
}

void ReferenceTechnique::allocatePool(std::uint64_t nodes) {
    nodes_ = gpu::Buffer();
    nodes_.setStorage(nodes * kNodeBytes, nullptr);
    stats_.poolNodes = nodes;
}

void ReferenceTechnique::resize(const pass::Context& targets) {
    width_ = targets.width;
    height_ = targets.height;
    heads_ = gpu::Texture(GL_TEXTURE_2D);
    heads_.storage2D(1, GL_R32UI, width_, height_);
    fragmentCounts_ = gpu::Texture(GL_TEXTURE_2D);
    fragmentCounts_.storage2D(1, GL_R32F, width_, height_)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    framebuffer_ = gpu::Framebuffer();
    // Depth only: fragments behind opaque surfaces fail the (early) depth test and append
    // nothing; no color target is written.
    framebuffer_.attach(GL_DEPTH_ATTACHMENT, *targets.depth).drawBuffers({GL_NONE});
    framebuffer_.checkComplete("oit/reference");
    const std::uint64_t pixels = static_cast<std::uint64_t>(width_) * height_;
    std::uint64_t nodes = std::max<std::uint64_t>(limits_.initialNodesPerPixel * pixels, 4096);
    allocatePool(std::min(nodes, maxPoolNodes_));
}

void ReferenceTechnique::beginAccumulate(int pass, const pass::Context& targets,
                                         const gpu::Program& program) {
    if (pass == 0) {
        // A new accumulation (first or repeated): empty lists, zero counters.
        const GLuint end = kEndOfList;
        glClearTexImage(heads_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &end);
        const GLuint zero = 0;
        glClearNamedBufferData(counters_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    }
    framebuffer_.bind();
    targets.state->apply(accumulationState(targets));
    glBindImageTexture(VEIL_IMG_OIT_REF_HEADS, heads_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_R32UI);
    nodes_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_OIT_REF_NODES);
    counters_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_OIT_REF_COUNTERS);
    prepareProgram(pass, program);
}

void ReferenceTechnique::prepareProgram(int, const gpu::Program& program) const {
    program.set("oitRefCapacity", static_cast<unsigned>(stats_.poolNodes));
}

void ReferenceTechnique::endAccumulate(int) {
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

bool ReferenceTechnique::repeatAccumulation() {
    GLuint requested = 0;
    glGetNamedBufferSubData(counters_.id(), 0, sizeof(GLuint), &requested);
    const bool atCap = stats_.poolNodes >= maxPoolNodes_;
    if (requested <= stats_.poolNodes || (limits_.dropPastCap && atCap)) {
        // "drop": the pool is at its cap; emit.glsl skipped the nodes past it (counted only).
        stats_.poolDroppedFragments =
            requested > stats_.poolNodes ? requested - stats_.poolNodes : 0;
        stats_.fragments = requested - stats_.poolDroppedFragments;
        stats_.accumulationRepeats = repeatsThisFrame_;
        repeatsThisFrame_ = 0;
        return false;
    }
    // The counter kept counting past the pool: it is the exact node count this frame needs.
    VEIL_CHECK(requested <= maxPoolNodes_ || limits_.dropPastCap,
               "reference OIT: the frame has {} transparent fragments ({:.1f} MiB of nodes) but "
               "the node pool is capped at {} nodes ({:.1f} MiB); lower the resolution or the "
               "transparent depth complexity, raise render.oit.max_pool_mib, or set "
               "render.oit.pool_overflow=drop",
               requested, mib(std::uint64_t(requested) * kNodeBytes), maxPoolNodes_,
               mib(maxPoolNodes_ * kNodeBytes));
    const std::uint64_t grown = std::min(nextPowerOfTwo(requested), maxPoolNodes_);
    log::info("reference OIT: node pool {} -> {} nodes ({:.1f} MiB) for {} fragments",
              stats_.poolNodes, grown, mib(grown * kNodeBytes), requested);
    allocatePool(grown);
    ++stats_.poolGrowths;
    ++repeatsThisFrame_;
    return true;
}

void ReferenceTechnique::resolve(const pass::Context& targets) {
    const gpu::Program& program = programs_.get(resolveProgram_);
    program.use();
    program.set("oitRefCapacity", static_cast<unsigned>(stats_.poolNodes));
    glBindImageTexture(VEIL_IMG_OIT_REF_HEADS, heads_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glBindImageTexture(VEIL_IMG_OIT_REF_TARGET, targets.hdrColor->id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_RGBA16F);
    glBindImageTexture(VEIL_IMG_OIT_REF_COUNT, fragmentCounts_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       GL_R32F);
    nodes_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_OIT_REF_NODES);
    counters_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_OIT_REF_COUNTERS);
    dispatchRegion(program, frameRegion(targets));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint counters[3] = {0, 0, 0};
    glGetNamedBufferSubData(counters_.id(), 0, sizeof(counters), counters);
    stats_.pixelOverflowFragments = counters[1];
    stats_.maxListLength = counters[2];
    if (counters[1] > 0 && !warnedOverflow_) {
        warnedOverflow_ = true;
        log::warn("reference OIT: {} fragments beyond the {} nearest per pixel were dropped "
                  "(the deepest pixel has {}; the image is exact only for the nearest {}); raise "
                  "render.oit.max_fragments_per_pixel to at least {}",
                  counters[1], limits_.maxFragmentsPerPixel, counters[2],
                  limits_.maxFragmentsPerPixel, counters[2]);
    }
}

std::size_t ReferenceTechnique::bytesPerPixel() const {
    const std::uint64_t pixels = std::max<std::uint64_t>(1, std::uint64_t(width_) * height_);
    return 4 + 4 + static_cast<std::size_t>((stats_.poolNodes * kNodeBytes + pixels - 1) / pixels);
}

nlohmann::json ReferenceTechnique::stats() const {
    return {{"fragments", stats_.fragments},
            {"pool_nodes", stats_.poolNodes},
            {"pool_mib", mib(stats_.poolNodes * kNodeBytes)},
            {"pool_growths", stats_.poolGrowths},
            {"accumulation_repeats", stats_.accumulationRepeats},
            {"pixel_overflow_fragments", stats_.pixelOverflowFragments},
            {"max_list_length", stats_.maxListLength},
            {"max_fragments_per_pixel", limits_.maxFragmentsPerPixel},
            {"pool_dropped_fragments", stats_.poolDroppedFragments}};
}

void registerReference(Registry& registry) {
    PropertySchema schema;
    schema
        .integer("initial_nodes_per_pixel", 4, 1, 1024,
                 "starting node-pool size per pixel (the pool grows by powers of two)")
        .real("max_pool_mib", 1024.0, 1.0 / 1024.0, 65536.0,
              "cap on the node pool in MiB (also capped by GL_MAX_SHADER_STORAGE_BLOCK_SIZE)")
        .integer("max_fragments_per_pixel", ReferenceTechnique::kDefaultMaxFragmentsPerPixel, 1,
                 512,
                 "fragments per pixel the resolve sorts (its local array); deeper pixels keep "
                 "the nearest and the rest are counted as dropped")
        .choice("pool_overflow", "error", {"error", "drop"},
                "past the cap: an error, or keep the capped pool and leave out (and count) the "
                "fragments that do not fit");
    registry.add({"reference",
                  "exact per-pixel sorted compositing (per-pixel linked lists, compute resolve)",
                  nullptr,
                  [](gpu::ProgramManager& programs, const Properties& p) {
                      ReferenceLimits limits;
                      limits.initialNodesPerPixel =
                          static_cast<std::uint64_t>(p.getInt("initial_nodes_per_pixel"));
                      limits.maxPoolBytes =
                          static_cast<std::uint64_t>(p.getDouble("max_pool_mib") * 1024.0 * 1024.0);
                      limits.maxFragmentsPerPixel = p.getInt("max_fragments_per_pixel");
                      limits.dropPastCap = p.getString("pool_overflow") == "drop";
                      return std::make_unique<ReferenceTechnique>(programs, limits);
                  },
                  std::move(schema),
                  true});
}

} // namespace veil::oit
