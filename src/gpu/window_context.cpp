#include "gpu/window_context.h"

#include "base/error.h"
#include "gpu/gl.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace veil::gpu {

namespace {
std::string lastGlfwError() {
    const char* description = nullptr;
    glfwGetError(&description);
    return description ? description : "unknown GLFW error";
}
} // namespace

WindowContext::WindowContext(int width, int height, const std::string& title, bool debug) {
    VEIL_CHECK(glfwInit() == GLFW_TRUE,
               "no window: GLFW could not initialise ({}); use "
               "`veil render` for headless rendering",
               lastGlfwError());
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        std::string why = lastGlfwError();
        glfwTerminate();
        throw Error(fmt::format("no OpenGL 4.5 core window: {}", why));
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(1);
    info_ = queryContextInfo();
    if (debug) enableDebugOutput();
}

WindowContext::~WindowContext() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

bool WindowContext::shouldClose() const { return glfwWindowShouldClose(window_); }
void WindowContext::swapBuffers() { glfwSwapBuffers(window_); }
void WindowContext::pollEvents() { glfwPollEvents(); }
void WindowContext::framebufferSize(int& width, int& height) const {
    glfwGetFramebufferSize(window_, &width, &height);
}

} // namespace veil::gpu
