// The declared-state tracker (src/gpu/pipeline_state.h): what it applies is what GL reports,
// a repeated state costs no GL call, one changed field costs one, and invalidate() forces all.
#include "gl/gl_fixture.h"

#include "gpu/gl.h"
#include "gpu/objects.h"
#include "gpu/pipeline_state.h"

#include <gtest/gtest.h>

namespace veil::test {

class PipelineStateGLTest : public GlTest {};

namespace {

gpu::PipelineState busyState() {
    gpu::PipelineState s;
    s.view(64, 32, 3, 4).depth(GL_LEQUAL, false);
    s.blend[0] = gpu::BlendState::separate(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE);
    s.blend[1] = gpu::BlendState::func(GL_ZERO, GL_ONE_MINUS_SRC_COLOR, GL_MAX);
    s.colorMask[2] = glm::bvec4(true, false, true, false);
    s.cull = true;
    s.cullFace = GL_FRONT;
    s.frontFace = GL_CW;
    s.logicOp = true;
    s.logicOpMode = GL_XOR;
    s.polygonOffsetFill = true;
    s.polygonOffsetFactor = 1.5f;
    s.polygonOffsetUnits = -2.0f;
    s.stencilTest = true;
    s.stencilFront = {GL_EQUAL, 3, 0xFF, 0x0F, GL_KEEP, GL_INCR_WRAP, GL_KEEP};
    s.stencilBack = {GL_ALWAYS, 0, 0xFF, 0xF0, GL_KEEP, GL_DECR_WRAP, GL_KEEP};
    s.depthClamp = true;
    s.multisample = false;
    s.scissorTest = true;
    s.scissor = {1, 2, 30, 20};
    return s;
}

// Names the fields that differ, for the failure message.
std::string differences(const gpu::PipelineState& a, const gpu::PipelineState& b) {
    std::string d;
    for (int i = 0; i < gpu::PipelineState::kTargets; ++i) {
        if (!(a.blend[i] == b.blend[i])) d += " blend[" + std::to_string(i) + "]";
        if (a.colorMask[i] != b.colorMask[i]) d += " colorMask[" + std::to_string(i) + "]";
    }
    auto check = [&](bool same, const char* name) {
        if (!same) d += std::string(" ") + name;
    };
    check(a.depthTest == b.depthTest && a.depthFunc == b.depthFunc && a.depthWrite == b.depthWrite,
          "depth");
    check(a.depthClamp == b.depthClamp, "depthClamp");
    check(a.stencilTest == b.stencilTest, "stencilTest");
    check(a.stencilFront == b.stencilFront, "stencilFront");
    check(a.stencilBack == b.stencilBack, "stencilBack");
    check(a.cull == b.cull && a.cullFace == b.cullFace && a.frontFace == b.frontFace, "cull");
    check(a.logicOp == b.logicOp && a.logicOpMode == b.logicOpMode, "logicOp");
    check(a.polygonOffsetFill == b.polygonOffsetFill &&
              a.polygonOffsetFactor == b.polygonOffsetFactor &&
              a.polygonOffsetUnits == b.polygonOffsetUnits,
          "polygonOffset");
    check(a.multisample == b.multisample, "multisample");
    check(a.conservativeRasterNV == b.conservativeRasterNV, "conservativeRasterNV");
    check(a.viewport == b.viewport, "viewport");
    check(a.scissorTest == b.scissorTest && a.scissor == b.scissor, "scissor");
    return d;
}

} // namespace

TEST_F(PipelineStateGLTest, AppliedStateIsWhatGlReports) {
    // The stencil reference reads back clamped to the bound framebuffer's stencil bits.
    gpu::Texture depthStencil(GL_TEXTURE_2D);
    depthStencil.storage2D(1, GL_DEPTH24_STENCIL8, 64, 32);
    gpu::Framebuffer fbo;
    fbo.attach(GL_DEPTH_STENCIL_ATTACHMENT, depthStencil);
    fbo.checkComplete("stencil test target");
    fbo.bind();
    gpu::StateTracker tracker;
    const gpu::PipelineState s = busyState();
    tracker.apply(s);
    EXPECT_EQ(differences(gpu::StateTracker::query(), s), "");
    // And back to the defaults: nothing of the busy state survives.
    gpu::PipelineState defaults;
    defaults.view(64, 32, 3, 4);
    tracker.apply(defaults);
    gpu::PipelineState read = gpu::StateTracker::query();
    read.scissor = defaults.scissor; // the box is kept while the test is off; not part of it
    EXPECT_EQ(differences(read, defaults), "");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(PipelineStateGLTest, OnlyChangesAreSent) {
    gpu::StateTracker tracker;
    const gpu::PipelineState s = busyState();
    tracker.apply(s);
    EXPECT_GT(tracker.lastCallCount(), 40); // everything, the first time
    tracker.apply(s);
    EXPECT_EQ(tracker.lastCallCount(), 0);
    gpu::PipelineState t = s;
    t.depthFunc = GL_GREATER;
    tracker.apply(t);
    EXPECT_EQ(tracker.lastCallCount(), 1);
    t.blend[1].enabled = false;
    tracker.apply(t);
    EXPECT_EQ(tracker.lastCallCount(), 1);
    // A raw GL call behind the tracker's back is repaired only after invalidate().
    glDepthFunc(GL_ALWAYS);
    tracker.invalidate();
    tracker.apply(t);
    EXPECT_GT(tracker.lastCallCount(), 40);
    GLint func = 0;
    glGetIntegerv(GL_DEPTH_FUNC, &func);
    EXPECT_EQ(func, GL_GREATER);
    tracker.apply(gpu::PipelineState{});
    VEIL_EXPECT_NO_GL_ERROR();
}

// The scissor limit (the viewer's tiled refinement): every state applied under it has the
// scissor test on with its own box clipped to the limit (the limit itself for a state without
// one), what GL then reports; clearing it gives the states their own scissor back.
TEST_F(PipelineStateGLTest, ScissorLimitClipsEveryAppliedState) {
    gpu::StateTracker tracker;
    auto box = [] {
        glm::ivec4 b(0);
        glGetIntegerv(GL_SCISSOR_BOX, &b.x);
        return b;
    };
    tracker.setScissorLimit(glm::ivec4(10, 5, 20, 8)); // x 10..30, y 5..13
    gpu::PipelineState plain;
    plain.view(64, 32);
    tracker.apply(plain);
    EXPECT_TRUE(glIsEnabled(GL_SCISSOR_TEST));
    EXPECT_EQ(box(), glm::ivec4(10, 5, 20, 8));
    gpu::PipelineState own = plain;
    own.scissorTest = true;
    own.scissor = {25, 0, 30, 10}; // x 25..55, y 0..10: clipped to x 25..30, y 5..10
    tracker.apply(own);
    EXPECT_EQ(box(), glm::ivec4(25, 5, 5, 5));
    own.scissor = {40, 0, 5, 5}; // outside: an empty box
    tracker.apply(own);
    EXPECT_EQ(box(), glm::ivec4(40, 5, 0, 0));
    tracker.setScissorLimit(std::nullopt);
    tracker.apply(plain);
    EXPECT_FALSE(glIsEnabled(GL_SCISSOR_TEST));
    own.scissor = {1, 2, 3, 4};
    tracker.apply(own);
    EXPECT_EQ(box(), glm::ivec4(1, 2, 3, 4));
    tracker.apply(gpu::PipelineState{});
    VEIL_EXPECT_NO_GL_ERROR();
}

} // namespace veil::test
