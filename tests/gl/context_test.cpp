#include "gl_fixture.h"

#include "base/error.h"
#include "gpu/gl.h"

#include <cstdlib>

namespace veil::test {

class ContextTest : public GlTest {};

TEST_F(ContextTest, HeadlessContextIsGl45Core) {
    GLint major = 0, minor = 0, profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_GE(major * 10 + minor, 45);
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
    EXPECT_FALSE(info().renderer.empty());
    EXPECT_GE(info().maxDrawBuffers, 8);
    EXPECT_GE(info().deviceIndex, 0);
    VEIL_EXPECT_NO_GL_ERROR();
}

TEST_F(ContextTest, MissingDeviceFailsClearly) {
    // A device index past the last one must be refused with a message, not a crash.
    gpu::HeadlessOptions options;
    options.deviceIndex = 999;
    try {
        gpu::HeadlessContext second(options);
        FAIL() << "expected veil::Error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("EGL device 999"), std::string::npos) << e.what();
    }
    context_->makeCurrent();
}

TEST_F(ContextTest, BadDeviceVariableFailsClearly) {
    ::setenv("VEIL_EGL_DEVICE", "gpu0", 1);
    EXPECT_THROW(gpu::HeadlessContext second, Error);
    ::unsetenv("VEIL_EGL_DEVICE");
    context_->makeCurrent();
}

} // namespace veil::test
