// GL 4.5 core contexts: headless through the EGL device platform (Mesa llvmpipe on CPU
// machines, NVIDIA on the GPU machine), and the facts every pass needs about the driver.
#pragma once

#include <memory>
#include <string>

namespace veil::gpu {

struct ContextInfo {
    std::string vendor;
    std::string renderer;
    std::string version;
    std::string eglDevice; // EGL device extensions / description, headless only
    int deviceIndex = -1;
    int cudaDevice = -1;      // EGL_CUDA_DEVICE_NV of the device, -1 when not reported
    std::string deviceChoice; // what chose the device (gpu/device_choice.h), for logs
    int maxSamples = 0;
    int maxDrawBuffers = 0;
    int max3DTextureSize = 0;
    int timerQueryBits = 0;
    bool softwareRenderer = false;        // llvmpipe / softpipe / swrast: timer queries unusable
    bool conservativeRaster = false;      // GL_NV_conservative_raster
    bool fragmentShaderInterlock = false; // GL_ARB_fragment_shader_interlock
    bool hasExtension(const std::string& name) const;
    std::string extensions; // space separated, with a leading and trailing space
};

// Reads ContextInfo from the current context and routes GL debug output to veil::log.
ContextInfo queryContextInfo();
void enableDebugOutput();

struct HeadlessOptions {
    // EGL device index; -1 = VEIL_EGL_DEVICE, else the GPU the scheduler allowed
    // (CUDA_VISIBLE_DEVICES, SLURM_STEP_GPUS, SLURM_JOB_GPUS, slot VEIL_GPU_SLOT; see
    // gpu/device_choice.h), else the first device that gives a 4.5 core context.
    int deviceIndex = -1;
    bool debug = false; // a debug context with GL debug output routed to the logger
};

// A surfaceless GL 4.5 core context on an EGL device, current on the creating thread for its
// lifetime. Render into framebuffer objects. Throws veil::Error saying what was tried when no
// device gives a context.
class HeadlessContext {
public:
    explicit HeadlessContext(const HeadlessOptions& options = {});
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    const ContextInfo& info() const { return info_; }
    void makeCurrent();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    ContextInfo info_;
};

} // namespace veil::gpu
