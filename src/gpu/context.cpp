#include "gpu/context.h"

#include "base/error.h"
#include "base/log.h"
#include "gpu/device_choice.h"
#include "gpu/gl.h"

#include <epoxy/egl.h>

#include <cstdlib>
#include <vector>

namespace veil::gpu {

bool ContextInfo::hasExtension(const std::string& name) const {
    return extensions.find(" " + name + " ") != std::string::npos;
}

namespace {
std::string glString(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

void GLAPIENTRY debugCallback(GLenum, GLenum type, GLuint id, GLenum severity, GLsizei length,
                              const GLchar* message, const void*) {
    std::string_view text(message, length > 0 ? static_cast<std::size_t>(length) : 0);
    if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH)
        log::error("GL [{}]: {}", id, text);
    else if (severity == GL_DEBUG_SEVERITY_MEDIUM)
        log::warn("GL [{}]: {}", id, text);
    else
        log::debug("GL [{}]: {}", id, text);
}
} // namespace

ContextInfo queryContextInfo() {
    ContextInfo info;
    info.vendor = glString(GL_VENDOR);
    info.renderer = glString(GL_RENDERER);
    info.version = glString(GL_VERSION);
    glGetIntegerv(GL_MAX_SAMPLES, &info.maxSamples);
    glGetIntegerv(GL_MAX_DRAW_BUFFERS, &info.maxDrawBuffers);
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info.max3DTextureSize);
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &info.timerQueryBits);
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    info.extensions.assign(1, ' ');
    for (GLint i = 0; i < count; ++i) {
        info.extensions.append(reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, i)));
        info.extensions.push_back(' ');
    }
    for (const char* soft : {"llvmpipe", "softpipe", "swrast", "SWR"})
        if (info.renderer.find(soft) != std::string::npos) info.softwareRenderer = true;
    info.conservativeRaster = info.hasExtension("GL_NV_conservative_raster");
    info.fragmentShaderInterlock = info.hasExtension("GL_ARB_fragment_shader_interlock");
    return info;
}

void enableDebugOutput() {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
}

struct HeadlessContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
};

namespace {
const char* eglErrorName(EGLint e) {
    switch (e) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    default:
        return "EGL error";
    }
}

// Tries one device; returns an empty string on success or why it failed.
std::string tryDevice(EGLDeviceEXT device, bool debug, EGLDisplay& dpyOut, EGLContext& ctxOut) {
    EGLDisplay dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
    if (dpy == EGL_NO_DISPLAY) return "no display for the device";
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor))
        return fmt::format("eglInitialize failed ({})", eglErrorName(eglGetError()));
    const char* exts = eglQueryString(dpy, EGL_EXTENSIONS);
    std::string extensions = exts ? exts : "";
    auto fail = [&](std::string why) {
        eglTerminate(dpy);
        return why;
    };
    if (extensions.find("EGL_KHR_surfaceless_context") == std::string::npos)
        return fail("no EGL_KHR_surfaceless_context");
    if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API) failed");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (extensions.find("EGL_KHR_no_config_context") == std::string::npos) {
        const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint n = 0;
        if (!eglChooseConfig(dpy, configAttribs, &config, 1, &n) || n < 1)
            return fail("no EGL config with OpenGL");
    }
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_CONTEXT_OPENGL_DEBUG,
                                 debug ? EGL_TRUE : EGL_FALSE,
                                 EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctxAttribs);
    if (ctx == EGL_NO_CONTEXT)
        return fail(fmt::format("no OpenGL 4.5 core context ({})", eglErrorName(eglGetError())));
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        eglDestroyContext(dpy, ctx);
        return fail("eglMakeCurrent failed");
    }
    dpyOut = dpy;
    ctxOut = ctx;
    return {};
}
} // namespace

HeadlessContext::HeadlessContext(const HeadlessOptions& options) : impl_(std::make_unique<Impl>()) {
    const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const std::string client = clientExts ? clientExts : "";
    log::debug("EGL client extensions: {}", client.empty() ? "(none)" : client);
    // Entry points through eglGetProcAddress: some glvnd setups list the device extensions
    // only once a vendor library is loaded, so the string alone is not a reliable test.
    auto queryDevices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    VEIL_CHECK(queryDevices && eglGetProcAddress("eglGetPlatformDisplayEXT"),
               "no headless OpenGL: the EGL library has no EGL_EXT_device_enumeration / "
               "EGL_EXT_platform_device (client extensions: '{}'; install Mesa's libegl-mesa0 "
               "and libgl1-mesa-dri, or an NVIDIA driver)",
               client);
    EGLint count = 0;
    if (!queryDevices(0, nullptr, &count)) count = 0;
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    if (count > 0) queryDevices(count, devices.data(), &count);
    VEIL_CHECK(count > 0, "no headless OpenGL: EGL reports no devices");
    // What each device is (software or not, its CUDA ordinal), for the choice by what the
    // scheduler allowed (gpu/device_choice.h).
    auto queryAttrib = reinterpret_cast<PFNEGLQUERYDEVICEATTRIBEXTPROC>(
        eglGetProcAddress("eglQueryDeviceAttribEXT"));
    std::vector<EglDeviceFacts> facts(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        const char* e =
            eglQueryDeviceStringEXT(devices[static_cast<std::size_t>(i)], EGL_EXTENSIONS);
        const std::string exts = e ? e : "";
        EglDeviceFacts& f = facts[static_cast<std::size_t>(i)];
        f.software = exts.find("EGL_MESA_device_software") != std::string::npos;
        EGLAttrib cuda = -1;
        if (queryAttrib && exts.find("EGL_NV_device_cuda") != std::string::npos &&
            queryAttrib(devices[static_cast<std::size_t>(i)], EGL_CUDA_DEVICE_NV, &cuda))
            f.cudaDevice = static_cast<int>(cuda);
        log::debug("EGL device {}: extensions '{}', CUDA device {}", i, exts, f.cudaDevice);
    }
    const DeviceChoice choice =
        chooseDevice(facts, deviceRequestFromEnvironment(options.deviceIndex));
    // The chosen device first; unless it was named explicitly, the others after it.
    std::vector<int> order{choice.index};
    if (!choice.strict)
        for (int i = 0; i < count; ++i)
            if (i != choice.index) order.push_back(i);

    std::string tried;
    for (int i : order) {
        std::string why = tryDevice(devices[static_cast<std::size_t>(i)], options.debug,
                                    impl_->display, impl_->context);
        if (why.empty()) {
            info_ = queryContextInfo();
            info_.deviceIndex = i;
            const char* devExts =
                eglQueryDeviceStringEXT(devices[static_cast<std::size_t>(i)], EGL_EXTENSIONS);
            info_.eglDevice = devExts ? devExts : "";
            info_.cudaDevice = facts[static_cast<std::size_t>(i)].cudaDevice;
            info_.deviceChoice = i == choice.index ? choice.why
                                                   : fmt::format("device {} failed ({}), the next "
                                                                 "that works",
                                                                 choice.index, tried);
            int glMajor = 0, glMinor = 0;
            glGetIntegerv(GL_MAJOR_VERSION, &glMajor);
            glGetIntegerv(GL_MINOR_VERSION, &glMinor);
            if (glMajor * 10 + glMinor >= 45) break;
            why = fmt::format("context is OpenGL {}.{}, 4.5 needed", glMajor, glMinor);
            eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(impl_->display, impl_->context);
            eglTerminate(impl_->display);
            impl_->display = EGL_NO_DISPLAY;
            impl_->context = EGL_NO_CONTEXT;
        }
        tried += fmt::format(" device {}: {};", i, why);
    }
    VEIL_CHECK(impl_->context != EGL_NO_CONTEXT, "no headless OpenGL 4.5 context:{}", tried);
    if (options.debug) enableDebugOutput();
    log::info("EGL device {}: {} ({}); chosen by {}", info_.deviceIndex, info_.renderer,
              info_.version, info_.deviceChoice);
}

HeadlessContext::~HeadlessContext() {
    if (impl_->display != EGL_NO_DISPLAY) {
        eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(impl_->display, impl_->context);
        // Not eglTerminate: Mesa shares the device display between contexts in a process, and
        // terminating it under another live context breaks that one.
    }
}

void HeadlessContext::makeCurrent() {
    VEIL_CHECK(eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context),
               "eglMakeCurrent failed");
}

} // namespace veil::gpu
