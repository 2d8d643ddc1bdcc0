#include "gpu/pipeline_state.h"

#include <algorithm>
#include <limits>

namespace veil::gpu {

BlendState BlendState::func(GLenum src, GLenum dst, GLenum equation) {
    return {true, src, dst, src, dst, equation, equation};
}

BlendState BlendState::separate(GLenum srcRgb, GLenum dstRgb, GLenum srcAlpha, GLenum dstAlpha,
                                GLenum equation) {
    return {true, srcRgb, dstRgb, srcAlpha, dstAlpha, equation, equation};
}

PipelineState& PipelineState::blendAll(const BlendState& b) {
    blend.fill(b);
    return *this;
}

PipelineState& PipelineState::depth(GLenum func, bool write) {
    depthTest = true;
    depthFunc = func;
    depthWrite = write;
    return *this;
}

PipelineState& PipelineState::view(int width, int height, int x, int y) {
    viewport = {x, y, width, height};
    return *this;
}

namespace {

void enable(GLenum cap, bool on) { on ? glEnable(cap) : glDisable(cap); }

void applyStencilFace(GLenum face, const StencilFace& s) {
    glStencilFuncSeparate(face, s.func, s.reference, s.readMask);
    glStencilMaskSeparate(face, s.writeMask);
    glStencilOpSeparate(face, s.stencilFail, s.depthFail, s.depthPass);
}

} // namespace

void StateTracker::apply(const PipelineState& state) {
    if (!limit_) return applyExactly(state);
    // Clipped to the limit: the scissor test on with the intersection of the boxes.
    PipelineState clipped = state;
    const glm::ivec4 l = *limit_;
    glm::ivec4 box = state.scissorTest ? state.scissor : l;
    const int x0 = std::max(box.x, l.x), y0 = std::max(box.y, l.y);
    const int x1 = std::min(box.x + box.z, l.x + l.z), y1 = std::min(box.y + box.w, l.y + l.w);
    clipped.scissorTest = true;
    clipped.scissor = glm::ivec4(x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0));
    applyExactly(clipped);
}

void StateTracker::applyExactly(const PipelineState& s) {
    const PipelineState* c = current_ ? &*current_ : nullptr;
    int calls = 0;
    // `changed(member)` is true when there is no cache or the cached value differs.
    auto changed = [&](auto PipelineState::*member) { return !c || c->*member != s.*member; };

    for (int i = 0; i < PipelineState::kTargets; ++i) {
        const BlendState& b = s.blend[i];
        const auto idx = static_cast<GLuint>(i);
        if (!c || c->blend[i].enabled != b.enabled) {
            b.enabled ? glEnablei(GL_BLEND, idx) : glDisablei(GL_BLEND, idx);
            ++calls;
        }
        // Factors are set even with blending off: a dual-source factor left on target 0 makes
        // a later multi-target draw an error on some drivers whatever the enable says.
        const BlendState* cb = c ? &c->blend[i] : nullptr;
        if (!cb || cb->srcRgb != b.srcRgb || cb->dstRgb != b.dstRgb || cb->srcAlpha != b.srcAlpha ||
            cb->dstAlpha != b.dstAlpha) {
            glBlendFuncSeparatei(idx, b.srcRgb, b.dstRgb, b.srcAlpha, b.dstAlpha);
            ++calls;
        }
        if (!cb || cb->equationRgb != b.equationRgb || cb->equationAlpha != b.equationAlpha) {
            glBlendEquationSeparatei(idx, b.equationRgb, b.equationAlpha);
            ++calls;
        }
        if (!c || c->colorMask[i] != s.colorMask[i]) {
            const glm::bvec4 m = s.colorMask[i];
            glColorMaski(idx, m.r, m.g, m.b, m.a);
            ++calls;
        }
    }
    if (changed(&PipelineState::depthTest)) enable(GL_DEPTH_TEST, s.depthTest), ++calls;
    if (changed(&PipelineState::depthFunc)) glDepthFunc(s.depthFunc), ++calls;
    if (changed(&PipelineState::depthWrite))
        glDepthMask(s.depthWrite ? GL_TRUE : GL_FALSE), ++calls;
    if (changed(&PipelineState::depthClamp)) enable(GL_DEPTH_CLAMP, s.depthClamp), ++calls;

    if (changed(&PipelineState::stencilTest)) enable(GL_STENCIL_TEST, s.stencilTest), ++calls;
    if (changed(&PipelineState::stencilFront))
        applyStencilFace(GL_FRONT, s.stencilFront), calls += 3;
    if (changed(&PipelineState::stencilBack)) applyStencilFace(GL_BACK, s.stencilBack), calls += 3;

    if (changed(&PipelineState::cull)) enable(GL_CULL_FACE, s.cull), ++calls;
    if (changed(&PipelineState::cullFace)) glCullFace(s.cullFace), ++calls;
    if (changed(&PipelineState::frontFace)) glFrontFace(s.frontFace), ++calls;

    if (changed(&PipelineState::logicOp)) enable(GL_COLOR_LOGIC_OP, s.logicOp), ++calls;
    if (changed(&PipelineState::logicOpMode)) glLogicOp(s.logicOpMode), ++calls;

    if (changed(&PipelineState::polygonOffsetFill))
        enable(GL_POLYGON_OFFSET_FILL, s.polygonOffsetFill), ++calls;
    if (changed(&PipelineState::polygonOffsetFactor) || changed(&PipelineState::polygonOffsetUnits))
        glPolygonOffset(s.polygonOffsetFactor, s.polygonOffsetUnits), ++calls;

    if (changed(&PipelineState::multisample)) enable(GL_MULTISAMPLE, s.multisample), ++calls;
    // Only touched when a pass asks for it, so drivers without the extension never see the enum.
    if ((c && c->conservativeRasterNV != s.conservativeRasterNV) ||
        (!c && s.conservativeRasterNV)) {
        enable(GL_CONSERVATIVE_RASTERIZATION_NV, s.conservativeRasterNV);
        ++calls;
    }

    if (s.viewport.z > 0 && (!c || c->viewport != s.viewport)) {
        glViewport(s.viewport.x, s.viewport.y, s.viewport.z, s.viewport.w);
        ++calls;
    }
    if (changed(&PipelineState::scissorTest)) enable(GL_SCISSOR_TEST, s.scissorTest), ++calls;
    if (s.scissorTest && (!c || c->scissor != s.scissor))
        glScissor(s.scissor.x, s.scissor.y, s.scissor.z, s.scissor.w), ++calls;

    // A viewport or scissor box the state leaves alone stays what the cache knew (or unknown,
    // -1, so the next state that states one sets it).
    PipelineState applied = s;
    if (s.viewport.z <= 0) applied.viewport = c ? c->viewport : glm::ivec4(-1);
    if (!s.scissorTest) applied.scissor = c ? c->scissor : glm::ivec4(-1);
    current_ = applied;
    calls_ = calls;
}

PipelineState StateTracker::query(bool hasConservativeRaster) {
    PipelineState s;
    auto on = [](GLenum cap) { return glIsEnabled(cap) == GL_TRUE; };
    auto integer = [](GLenum name) {
        GLint v = 0;
        glGetIntegerv(name, &v);
        return v;
    };
    auto integerAt = [](GLenum name, GLuint i) {
        GLint v = 0;
        glGetIntegeri_v(name, i, &v);
        return v;
    };
    for (int i = 0; i < PipelineState::kTargets; ++i) {
        const auto idx = static_cast<GLuint>(i);
        BlendState& b = s.blend[i];
        b.enabled = glIsEnabledi(GL_BLEND, idx) == GL_TRUE;
        b.srcRgb = static_cast<GLenum>(integerAt(GL_BLEND_SRC_RGB, idx));
        b.dstRgb = static_cast<GLenum>(integerAt(GL_BLEND_DST_RGB, idx));
        b.srcAlpha = static_cast<GLenum>(integerAt(GL_BLEND_SRC_ALPHA, idx));
        b.dstAlpha = static_cast<GLenum>(integerAt(GL_BLEND_DST_ALPHA, idx));
        b.equationRgb = static_cast<GLenum>(integerAt(GL_BLEND_EQUATION_RGB, idx));
        b.equationAlpha = static_cast<GLenum>(integerAt(GL_BLEND_EQUATION_ALPHA, idx));
        GLboolean m[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
        glGetBooleani_v(GL_COLOR_WRITEMASK, idx, m);
        s.colorMask[i] = glm::bvec4(m[0], m[1], m[2], m[3]);
    }
    s.depthTest = on(GL_DEPTH_TEST);
    s.depthFunc = static_cast<GLenum>(integer(GL_DEPTH_FUNC));
    GLboolean depthMask = GL_TRUE;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depthMask);
    s.depthWrite = depthMask == GL_TRUE;
    s.depthClamp = on(GL_DEPTH_CLAMP);
    s.stencilTest = on(GL_STENCIL_TEST);
    // GL returns unsigned masks through glGetIntegerv clamped to INT_MAX: all bits set.
    auto mask = [&](GLenum name) {
        const GLint v = integer(name);
        return v == std::numeric_limits<GLint>::max() ? ~0u : static_cast<GLuint>(v);
    };
    auto face = [&](bool back) {
        StencilFace f;
        f.func = static_cast<GLenum>(integer(back ? GL_STENCIL_BACK_FUNC : GL_STENCIL_FUNC));
        f.reference = integer(back ? GL_STENCIL_BACK_REF : GL_STENCIL_REF);
        f.readMask = mask(back ? GL_STENCIL_BACK_VALUE_MASK : GL_STENCIL_VALUE_MASK);
        f.writeMask = mask(back ? GL_STENCIL_BACK_WRITEMASK : GL_STENCIL_WRITEMASK);
        f.stencilFail = static_cast<GLenum>(integer(back ? GL_STENCIL_BACK_FAIL : GL_STENCIL_FAIL));
        f.depthFail = static_cast<GLenum>(
            integer(back ? GL_STENCIL_BACK_PASS_DEPTH_FAIL : GL_STENCIL_PASS_DEPTH_FAIL));
        f.depthPass = static_cast<GLenum>(
            integer(back ? GL_STENCIL_BACK_PASS_DEPTH_PASS : GL_STENCIL_PASS_DEPTH_PASS));
        return f;
    };
    s.stencilFront = face(false);
    s.stencilBack = face(true);
    s.cull = on(GL_CULL_FACE);
    s.cullFace = static_cast<GLenum>(integer(GL_CULL_FACE_MODE));
    s.frontFace = static_cast<GLenum>(integer(GL_FRONT_FACE));
    s.logicOp = on(GL_COLOR_LOGIC_OP);
    s.logicOpMode = static_cast<GLenum>(integer(GL_LOGIC_OP_MODE));
    s.polygonOffsetFill = on(GL_POLYGON_OFFSET_FILL);
    glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &s.polygonOffsetFactor);
    glGetFloatv(GL_POLYGON_OFFSET_UNITS, &s.polygonOffsetUnits);
    s.multisample = on(GL_MULTISAMPLE);
    s.conservativeRasterNV = hasConservativeRaster && on(GL_CONSERVATIVE_RASTERIZATION_NV);
    glGetIntegerv(GL_VIEWPORT, &s.viewport.x);
    s.scissorTest = on(GL_SCISSOR_TEST);
    glGetIntegerv(GL_SCISSOR_BOX, &s.scissor.x);
    return s;
}

} // namespace veil::gpu
