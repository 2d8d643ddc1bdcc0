#include "oit/wboit/wboit.h"

#include "shaders/common/bindings.h"

namespace veil::oit {

namespace {

class WboitTechnique final : public Technique {
public:
    explicit WboitTechnique(gpu::ProgramManager& programs) : programs_(programs) {
        resolveProgram_ = programs_.add(gpu::ProgramDesc::compute("oit/wboit/resolve.comp"));
    }
    std::string name() const override { return "wboit"; }
    std::filesystem::path emitInclude() const override { return "oit/wboit/emit.glsl"; }

    void resize(const pass::Context& targets) override {
        accum_ = gpu::Texture(GL_TEXTURE_2D);
        accum_.storage2D(1, GL_RGBA16F, targets.width, targets.height);
        revealage_ = gpu::Texture(GL_TEXTURE_2D);
        revealage_.storage2D(1, GL_R16F, targets.width, targets.height);
        framebuffer_ = gpu::Framebuffer();
        framebuffer_.attach(GL_COLOR_ATTACHMENT0, accum_)
            .attach(GL_COLOR_ATTACHMENT1, revealage_)
            .attach(GL_DEPTH_ATTACHMENT, *targets.depth)
            .drawBuffers({GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1});
        framebuffer_.checkComplete("oit/wboit");
    }

    void beginAccumulate(int, const pass::Context& targets, const gpu::Program&) override {
        framebuffer_.bind();
        gpu::PipelineState state = accumulationState(targets);
        state.blend[0] = gpu::BlendState::func(GL_ONE, GL_ONE);                  // A: sums
        state.blend[1] = gpu::BlendState::func(GL_ZERO, GL_ONE_MINUS_SRC_COLOR); // prod(1 - c)
        targets.state->apply(state);
        const float zero[4] = {0, 0, 0, 0}, one[4] = {1, 1, 1, 1};
        glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, zero);
        glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 1, one);
    }

    // The fog from compute through emit.glsl's OIT_WRITE (the two blend equations above).
    PerPixelEmit perPixelEmit(int) const override { return PerPixelEmit::Compute; }
    void bindPerPixelEmit(int, const pass::Context&) const override {
        glBindImageTexture(VEIL_IMG_OIT_TARGET0, accum_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                           GL_RGBA16F);
        glBindImageTexture(VEIL_IMG_OIT_TARGET0 + 1, revealage_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                           GL_R16F);
    }

    void endAccumulate(int) override { glBindFramebuffer(GL_FRAMEBUFFER, 0); }

    void resolve(const pass::Context& targets) override {
        const gpu::Program& program = programs_.get(resolveProgram_);
        program.use();
        accum_.bind(VEIL_TEX_OIT0);
        revealage_.bind(VEIL_TEX_OIT0 + 1);
        glBindImageTexture(VEIL_IMG_OIT_WBOIT_TARGET, targets.hdrColor->id(), 0, GL_FALSE, 0,
                           GL_READ_WRITE, GL_RGBA16F);
        dispatchRegion(program, frameRegion(targets));
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    }

    std::size_t bytesPerPixel() const override { return 8 + 2; }

    // [McGuire16 Eq. 5]: accum = sum of weighted premultiplied radiance (rgb) and coverage (a),
    // revealage = prod(1 - alpha).
    std::vector<Resource> resources() const override {
        return {{"oit.wboit.accum", [this] { return &accum_; }},
                {"oit.wboit.revealage", [this] { return &revealage_; }}};
    }

private:
    gpu::ProgramManager& programs_;
    gpu::ProgramHandle resolveProgram_;
    gpu::Texture accum_{gpu::NoCreate}, revealage_{gpu::NoCreate};
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
};

} // namespace

void registerWboit(Registry& registry) {
    registry.add({"wboit",
                  "weighted blended OIT ([McGuire13]; [McGuire16 Eq. 5] weight, Listing 2 "
                  "guards; grey revealage)",
                  nullptr,
                  [](gpu::ProgramManager& programs, const Properties&) {
                      return std::make_unique<WboitTechnique>(programs);
                  },
                  {},
                  true});
}

} // namespace veil::oit
