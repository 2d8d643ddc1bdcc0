#include "shadows/common/depth_maps.h"

namespace veil::shadows {

DepthMaps::DepthMaps(gpu::ProgramManager& programs)
    : programs_(programs), program_(programs.add(gpu::ProgramDesc::graphics(
                               "frame/mesh.vert", "shadows/common/depth.frag"))) {}

void DepthMaps::resize(int size, int layers) {
    if (size == size_ && layers == layers_) return;
    size_ = size;
    layers_ = layers;
    texture_ = gpu::Texture(GL_TEXTURE_2D_ARRAY);
    texture_.storage3D(1, GL_DEPTH_COMPONENT32F, size, size, std::max(layers, 1))
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE)
        .parameter(GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    framebuffer_ = gpu::Framebuffer();
}

void setCasterView(const gpu::Program& program, const LightView& view) {
    // Particles (billboards) face the light: the view's right and up axes.
    const glm::mat4 inv = glm::inverse(view.view);
    program.set("useOverride", 1)
        .set("viewProjection", view.viewProjection)
        .set("overrideRight", glm::vec3(inv[0]))
        .set("overrideUp", glm::vec3(inv[1]));
}

void DepthMaps::renderRows(const pass::Context& frame, int y0, int y1) {
    const gpu::Program& program = programs_.get(program_);
    for (const LightView& view : *frame.lightViews) {
        framebuffer_.attachLayer(GL_DEPTH_ATTACHMENT, texture_, view.layer).drawBuffers({GL_NONE});
        framebuffer_.bind();
        gpu::PipelineState s;
        s.view(size_, size_).depth(GL_LESS, true);
        if (y0 > 0 || y1 < size_) { // a band: the clear and the draws stay in its rows
            s.scissorTest = true;
            s.scissor = glm::ivec4(0, y0, size_, y1 - y0);
        }
        frame.state->apply(s); // before the clear: it obeys the depth mask
        const float one = 1.0f;
        glClearNamedFramebufferfv(framebuffer_.id(), GL_DEPTH, 0, &one);
        program.use();
        setCasterView(program, view);
        program.set("shadowView", view.layer);
        frame.drawObjects(program, pass::ObjectSet::OpaqueCasters);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

} // namespace veil::shadows
