#include "frame/stages/_template/template_stage.h"

#include "shaders/common/bindings.h"

namespace veil::frame {

const PropertySchema& TemplateStage::schema() {
    static const PropertySchema schema = [] {
        PropertySchema s;
        s.real("gain", 1.0, 0.0, 16.0, "multiplies the HDR radiance of every pixel", "");
        return s;
    }();
    return schema;
}

TemplateStage::TemplateStage(gpu::ProgramManager& programs, Properties properties)
    : programs_(programs), properties_(std::move(properties)),
      program_(programs.add(gpu::ProgramDesc::compute("frame/_template/template.comp"))) {}

std::vector<pass::Pass> TemplateStage::passes(const pass::Assembly&) {
    // Declared: reads hdr, writes hdr (the frame checks that an earlier pass wrote it).
    pass::Pass p{"template", {"hdr"}, {"hdr"}, [this](const pass::Context& context) {
                     const glm::ivec4 r = context.region;
                     const gpu::Program& program = programs_.get(program_);
                     program.use();
                     program.set("gain", properties_.getFloat("gain")).set("region", r);
                     glBindImageTexture(VEIL_IMG_OUTPUT, context.hdrColor->id(), 0, GL_FALSE, 0,
                                        GL_READ_WRITE, GL_RGBA16F);
                     glDispatchCompute((r.z - r.x + 7) / 8, (r.w - r.y + 7) / 8, 1);
                     // The next pass reads hdr as a texture or image.
                     glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT |
                                     GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
                 }};
    p.scope = pass::Scope::Pixels;
    return {std::move(p)};
}

} // namespace veil::frame
