// Declared fixed-function GL state (docs/architecture.md "Declared GL state": a pass sets all the
// state it needs and relies on none that another pass left behind). Each pass or sub-pass describes
// its blend (per draw buffer), depth, stencil, cull, logic-op, polygon offset, viewport,
// multisample and colour-mask state as one PipelineState value; a StateTracker applies it, changing
// only what differs from what it applied last (Magnum's GL::Renderer state tracker is the model).
// Every field not stated keeps the default below, so a pass that does not blend says nothing about
// blending and still gets blending off: no pass depends on another's leftovers.
//
// The tracker's cache is only valid while nobody else changes the state: code that issues raw
// GL state calls or foreign code (Dear ImGui) must be followed by invalidate(). The frame
// invalidates its tracker at the start of every frame.
#pragma once

#include "gpu/gl.h"

#include <glm/vec4.hpp>

#include <array>
#include <optional>

namespace veil::gpu {

struct BlendState {
    bool enabled = false;
    GLenum srcRgb = GL_ONE, dstRgb = GL_ZERO, srcAlpha = GL_ONE, dstAlpha = GL_ZERO;
    GLenum equationRgb = GL_FUNC_ADD, equationAlpha = GL_FUNC_ADD;

    // Blending on with the same factors for colour and alpha.
    static BlendState func(GLenum src, GLenum dst, GLenum equation = GL_FUNC_ADD);
    static BlendState separate(GLenum srcRgb, GLenum dstRgb, GLenum srcAlpha, GLenum dstAlpha,
                               GLenum equation = GL_FUNC_ADD);
    bool operator==(const BlendState&) const = default;
};

struct StencilFace {
    GLenum func = GL_ALWAYS;
    GLint reference = 0;
    GLuint readMask = ~0u, writeMask = ~0u;
    GLenum stencilFail = GL_KEEP, depthFail = GL_KEEP, depthPass = GL_KEEP;
    bool operator==(const StencilFace&) const = default;
};

struct PipelineState {
    static constexpr int kTargets = 8; // GL 4.5 guarantees 8 draw buffers

    std::array<BlendState, kTargets> blend{};
    std::array<glm::bvec4, kTargets> colorMask{glm::bvec4(true), glm::bvec4(true), glm::bvec4(true),
                                               glm::bvec4(true), glm::bvec4(true), glm::bvec4(true),
                                               glm::bvec4(true), glm::bvec4(true)};

    bool depthTest = false;
    GLenum depthFunc = GL_LESS;
    bool depthWrite = true;
    bool depthClamp = false;

    bool stencilTest = false;
    StencilFace stencilFront{}, stencilBack{};

    bool cull = false;
    GLenum cullFace = GL_BACK;
    GLenum frontFace = GL_CCW;

    bool logicOp = false;
    GLenum logicOpMode = GL_COPY;

    bool polygonOffsetFill = false;
    float polygonOffsetFactor = 0.0f, polygonOffsetUnits = 0.0f;

    bool multisample = true;
    bool conservativeRasterNV = false; // GL_NV_conservative_raster; only where the driver has it

    glm::ivec4 viewport{0, 0, 0, 0}; // x, y, width, height; width 0 = compute-only, not applied
    bool scissorTest = false;
    glm::ivec4 scissor{0, 0, 0, 0};

    // The same blend state on every draw buffer.
    PipelineState& blendAll(const BlendState& b);
    // Depth test on with `func`; `write` controls the depth mask.
    PipelineState& depth(GLenum func, bool write);
    PipelineState& view(int width, int height, int x = 0, int y = 0);

    bool operator==(const PipelineState&) const = default;
};

class StateTracker {
public:
    // Makes `state` the GL state, setting only what differs from the last applied state (all
    // of it after invalidate() or on first use).
    void apply(const PipelineState& state);
    // Forget what was applied: the next apply() sets everything.
    void invalidate() { current_.reset(); }
    // While set, every applied state is clipped to this box (x, y, width, height): the scissor
    // test on, with the state's own box intersected with it, so the draws and clears that
    // follow stay inside. The viewer's tiled refinement keeps a frame's passes to one screen
    // tile this way (frame/renderer.h, beginRefinement). nullopt: no limit (the default).
    void setScissorLimit(std::optional<glm::ivec4> box) {
        limit_ = box;
        current_.reset();
    }
    const std::optional<glm::ivec4>& scissorLimit() const { return limit_; }
    // GL calls the last apply() made (tests: a repeated apply makes none).
    int lastCallCount() const { return calls_; }
    // Reads the fixed-function state of the current context back from GL (tests, debugging).
    static PipelineState query(bool hasConservativeRaster = false);

private:
    void applyExactly(const PipelineState& state);
    std::optional<PipelineState> current_;
    std::optional<glm::ivec4> limit_;
    int calls_ = 0;
};

} // namespace veil::gpu
