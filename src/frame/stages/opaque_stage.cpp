#include "frame/stages/opaque_stage.h"

#include "scene/scene.h"
#include "shaders/common/bindings.h"

namespace veil::frame {

std::vector<pass::Pass> OpaqueStage::passes(const pass::Assembly& assembly) {
    const auto execute = [this](const pass::Context& context) { draw(context); };
    if (mode_ == Mode::DepthPrepass) return {{"depth", {}, {"depth"}, execute}};
    std::vector<std::string> reads;
    if (assembly.has("ao.visibility")) reads.push_back("ao.visibility");
    pass::Pass p{"opaque", std::move(reads), {"depth", "hdr"}, execute};
    p.receivesShadows = true;
    return {std::move(p)};
}

void OpaqueStage::resize(pass::Context& context) {
    fbo_ = gpu::Framebuffer();
    fbo_.attach(GL_COLOR_ATTACHMENT0, *context.hdrColor)
        .attach(GL_DEPTH_ATTACHMENT, *context.depth)
        .drawBuffers({GL_COLOR_ATTACHMENT0});
    fbo_.checkComplete("opaque");
}

void OpaqueStage::draw(const pass::Context& context) const {
    const bool depthOnly = mode_ == Mode::DepthPrepass;
    const bool afterPrepass = mode_ == Mode::ShadedAfterPrepass;
    fbo_.bind();
    gpu::PipelineState state;
    state.view(context.width, context.height).depth(afterPrepass ? GL_LEQUAL : GL_LESS, true);
    if (depthOnly) state.colorMask[0] = glm::bvec4(false);
    context.state->apply(state); // before the clears: they obey the colour/depth masks
    const glm::vec4 bg(context.scene->render.background, 1.0f);
    const float one = 1.0f;
    if (!depthOnly) glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, &bg.x);
    if (!afterPrepass) glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
    const gpu::Program& program = programs_.get(program_);
    program.set("useOverride", 0);
    if (depthOnly) {
        program.set("depthPrepass", 1);
    } else if (afterPrepass) {
        program.set("depthPrepass", 0);
        context.ambientOcclusion->bind(VEIL_TEX_AO);
    }
    if (!depthOnly && context.prepareReceiver) context.prepareReceiver(program);
    context.drawObjects(program, pass::ObjectSet::Opaque);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

TonemapStage::TonemapStage(gpu::ProgramManager& programs)
    : programs_(programs), program_(programs.add(gpu::ProgramDesc::compute("frame/tonemap.comp"))) {
}

std::vector<pass::Pass> TonemapStage::passes(const pass::Assembly&) {
    pass::Pass p{"tonemap", {"hdr"}, {"ldr"}, [this](const pass::Context& context) {
                     const glm::ivec4 r = context.region;
                     const gpu::Program& program = programs_.get(program_);
                     program.use();
                     program.set("exposure", context.scene->render.exposure)
                         .set("operatorId", context.scene->render.tonemap == "clamp" ? 1 : 0)
                         .set("region", r);
                     context.hdrColor->bind(VEIL_TEX_HDR);
                     const gpu::Texture* ldr = context.resources->texture("ldr");
                     glBindImageTexture(VEIL_IMG_OUTPUT, ldr->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                                        GL_RGBA8);
                     glDispatchCompute((r.z - r.x + 7) / 8, (r.w - r.y + 7) / 8, 1);
                     glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
                 }};
    p.scope = pass::Scope::Pixels;
    return {std::move(p)};
}

} // namespace veil::frame
