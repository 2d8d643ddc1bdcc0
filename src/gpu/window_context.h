// A GL 4.5 core context with a window, through GLFW (for `veil view`).
#pragma once

#include "gpu/context.h"

#include <string>

struct GLFWwindow;

namespace veil::gpu {

class WindowContext {
public:
    // Throws veil::Error when GLFW has no display or no 4.5 core context.
    WindowContext(int width, int height, const std::string& title, bool debug = false);
    ~WindowContext();
    WindowContext(const WindowContext&) = delete;
    WindowContext& operator=(const WindowContext&) = delete;

    GLFWwindow* window() const { return window_; }
    const ContextInfo& info() const { return info_; }
    bool shouldClose() const;
    void swapBuffers();
    void pollEvents();
    void framebufferSize(int& width, int& height) const;

private:
    GLFWwindow* window_ = nullptr;
    ContextInfo info_;
};

} // namespace veil::gpu
