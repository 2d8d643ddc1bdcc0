#include "oit/_template/template.h"

namespace veil::oit {

namespace {

class TemplateTechnique final : public Technique {
public:
    explicit TemplateTechnique(float opacityScale) : opacityScale_(opacityScale) {}

    std::string name() const override { return "template"; }
    std::filesystem::path emitInclude() const override { return "oit/_template/emit.glsl"; }

    // Targets: the frame's HDR image itself (a technique with accumulation targets creates
    // them here, sized targets.width x targets.height).
    void resize(const pass::Context& targets) override {
        framebuffer_ = gpu::Framebuffer();
        framebuffer_.attach(GL_COLOR_ATTACHMENT0, *targets.hdrColor)
            .attach(GL_DEPTH_ATTACHMENT, *targets.depth)
            .drawBuffers({GL_COLOR_ATTACHMENT0});
        framebuffer_.checkComplete("oit/template");
    }

    // Declared state, applied through the frame's tracker; no raw GL state calls.
    void beginAccumulate(int pass, const pass::Context& targets,
                         const gpu::Program& program) override {
        framebuffer_.bind();
        gpu::PipelineState state = accumulationState(targets);
        state.blend[0] = gpu::BlendState::separate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
        targets.state->apply(state);
        prepareProgram(pass, program);
    }

    // Uniforms of the emit include, for the surface program and any other program drawn in
    // the pass (the fog's emission).
    void prepareProgram(int, const gpu::Program& program) const override {
        program.set("templateOpacityScale", opacityScale_);
    }

    void endAccumulate(int) override { glBindFramebuffer(GL_FRAMEBUFFER, 0); }
    void resolve(const pass::Context&) override {} // composited while accumulating
    std::size_t bytesPerPixel() const override { return 0; }
    nlohmann::json stats() const override { return {{"opacity_scale", opacityScale_}}; }

private:
    float opacityScale_;
    gpu::Framebuffer framebuffer_{gpu::NoCreate};
};

} // namespace

void registerTemplate(Registry& registry) {
    PropertySchema schema;
    schema.real("opacity_scale", 1.0, 0.0, 1.0, "multiplies every fragment's coverage alpha",
                "[McGuire16 Eq. 2] (alpha)");
    registry.add({"template", "copy me: unsorted dual-source blending with one property", nullptr,
                  [](gpu::ProgramManager&, const Properties& p) {
                      return std::make_unique<TemplateTechnique>(p.getFloat("opacity_scale"));
                  },
                  std::move(schema)});
}

} // namespace veil::oit
