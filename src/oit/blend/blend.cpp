#include "oit/blend/blend.h"

namespace veil::oit {

namespace {

class BlendTechnique final : public Technique {
public:
    std::string name() const override { return "blend"; }
    std::filesystem::path emitInclude() const override { return "oit/blend/emit.glsl"; }

    void resize(const OitFrameTargets& targets) override {
        framebuffer_ = gpu::Framebuffer();
        framebuffer_.attach(GL_COLOR_ATTACHMENT0, *targets.hdrColor)
            .attach(GL_DEPTH_ATTACHMENT, *targets.depth)
            .drawBuffers({GL_COLOR_ATTACHMENT0});
        framebuffer_.checkComplete("oit/blend");
    }

    void beginAccumulate(int, const OitFrameTargets& targets, const gpu::Program&) override {
        framebuffer_.bind();
        glViewport(0, 0, targets.width, targets.height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_FALSE);
        glDisable(GL_CULL_FACE);
        glEnable(GL_BLEND);
        // dst = src0 * 1 + dst * src1 (dual-source: per-channel modulation of the background)
        glBlendFuncSeparate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
        glBlendEquation(GL_FUNC_ADD);
    }

    void endAccumulate(int) override {
        glDisable(GL_BLEND);
        glDepthMask(GL_TRUE);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

    void resolve(const OitFrameTargets&) override {} // composited during accumulation
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
         {}});
}

} // namespace veil::oit
