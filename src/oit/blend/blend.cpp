#include "oit/blend/blend.h"

#include "shaders/common/bindings.h"

namespace veil::oit {

namespace {

class BlendTechnique final : public Technique {
public:
    std::string name() const override { return "blend"; }
    std::filesystem::path emitInclude() const override { return "oit/blend/emit.glsl"; }

    void resize(const pass::Context& targets) override {
        framebuffer_ = gpu::Framebuffer();
        framebuffer_.attach(GL_COLOR_ATTACHMENT0, *targets.hdrColor)
            .attach(GL_DEPTH_ATTACHMENT, *targets.depth)
            .drawBuffers({GL_COLOR_ATTACHMENT0});
        framebuffer_.checkComplete("oit/blend");
    }

    void beginAccumulate(int, const pass::Context& targets, const gpu::Program&) override {
        framebuffer_.bind();
        gpu::PipelineState state = accumulationState(targets);
        // dst = src0 * 1 + dst * src1 (dual-source: per-channel modulation of the background)
        state.blend[0] = gpu::BlendState::separate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
        targets.state->apply(state);
    }

    // The fog from compute: dst = src0 + src1 * dst on the HDR image (emit.glsl).
    PerPixelEmit perPixelEmit(int) const override { return PerPixelEmit::Compute; }
    void bindPerPixelEmit(int, const pass::Context& targets) const override {
        glBindImageTexture(VEIL_IMG_OIT_TARGET0, targets.hdrColor->id(), 0, GL_FALSE, 0,
                           GL_READ_WRITE, GL_RGBA16F);
    }

    void endAccumulate(int) override { glBindFramebuffer(GL_FRAMEBUFFER, 0); }

    void resolve(const pass::Context&) override {} // composited during accumulation
    std::size_t bytesPerPixel() const override { return 0; }

private:
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
};

} // namespace

void registerBlend(Registry& registry) {
    registry.add(
        {"blend",
         "unsorted alpha blending (single-pass baseline, order-dependent)",
         nullptr,
         [](gpu::ProgramManager&, const Properties&) { return std::make_unique<BlendTechnique>(); },
         {},
         true});
}

} // namespace veil::oit
