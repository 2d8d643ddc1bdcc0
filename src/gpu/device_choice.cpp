#include "gpu/device_choice.h"

#include "base/error.h"
#include "base/text.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdlib>

namespace veil::gpu {

namespace {

std::string env(const char* name, bool* set = nullptr) {
    const char* v = std::getenv(name);
    if (set) *set = v != nullptr;
    return v ? v : "";
}

// A non-negative integer, or -1 when `s` is not one.
int index(const std::string& s) {
    if (s.empty() || s.size() > 6) return -1;
    for (char c : s)
        if (c < '0' || c > '9') return -1;
    return std::atoi(s.c_str());
}

// "0,2" -> {0, 2}; "" when an entry is not an integer (UUIDs, MIG names) or the list is empty.
std::vector<int> integers(const std::string& list) {
    std::vector<int> out;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        const int v = index(list.substr(start, comma - start));
        if (v < 0) return {};
        out.push_back(v);
        start = comma + 1;
    }
    return out;
}

} // namespace

DeviceRequest deviceRequestFromEnvironment(int deviceOption) {
    DeviceRequest r;
    if (deviceOption >= 0) {
        r.index = deviceOption;
        r.indexFrom = "--device";
    } else if (const std::string v = env("VEIL_EGL_DEVICE"); !v.empty()) {
        r.index = index(v);
        VEIL_CHECK(r.index >= 0, "VEIL_EGL_DEVICE='{}' is not a device index (0, 1, ...)",
                   printable(v, 100));
        r.indexFrom = "VEIL_EGL_DEVICE";
    }
    r.cudaVisible = env("CUDA_VISIBLE_DEVICES", &r.cudaVisibleSet);
    r.slurmStepGpus = env("SLURM_STEP_GPUS");
    r.slurmJobGpus = env("SLURM_JOB_GPUS");
    if (const std::string v = env("VEIL_GPU_SLOT"); !v.empty()) {
        r.slot = index(v);
        VEIL_CHECK(r.slot >= 0, "VEIL_GPU_SLOT='{}' is not a non-negative integer",
                   printable(v, 100));
    }
    return r;
}

DeviceChoice chooseDevice(const std::vector<EglDeviceFacts>& devices, const DeviceRequest& r) {
    const int count = static_cast<int>(devices.size());
    VEIL_CHECK(count > 0, "no headless OpenGL: EGL reports no devices");
    if (r.index >= 0) {
        VEIL_CHECK(r.index < count, "EGL device {} (from {}): only {} EGL device(s) exist (0..{})",
                   r.index, r.indexFrom, count, count - 1);
        return {r.index, true, fmt::format("{} {}", r.indexFrom, r.index)};
    }
    std::vector<int> hardware;
    bool cudaOrdinals = false;
    for (int i = 0; i < count; ++i)
        if (!devices[static_cast<std::size_t>(i)].software) {
            hardware.push_back(i);
            cudaOrdinals = cudaOrdinals || devices[static_cast<std::size_t>(i)].cudaDevice >= 0;
        }
    auto software = [&](const std::string& why) -> DeviceChoice {
        for (int i = 0; i < count; ++i)
            if (devices[static_cast<std::size_t>(i)].software) return {i, false, why};
        return {0, false, why};
    };

    // The GPUs the scheduler allowed, and which variable said so.
    std::vector<int> allowed;
    std::string from;
    if (r.cudaVisibleSet) {
        if (r.cudaVisible.empty() || r.cudaVisible == "-1" || r.cudaVisible == "NoDevFiles")
            return software(fmt::format("CUDA_VISIBLE_DEVICES='{}' allows no GPU: software "
                                        "rendering",
                                        printable(r.cudaVisible, 100)));
        allowed = integers(r.cudaVisible);
        from = "CUDA_VISIBLE_DEVICES=" + printable(r.cudaVisible, 100);
    }
    if (allowed.empty() && !r.slurmStepGpus.empty()) {
        allowed = integers(r.slurmStepGpus);
        from = "SLURM_STEP_GPUS=" + printable(r.slurmStepGpus, 100);
    }
    if (allowed.empty() && !r.slurmJobGpus.empty()) {
        allowed = integers(r.slurmJobGpus);
        from = "SLURM_JOB_GPUS=" + printable(r.slurmJobGpus, 100);
    }
    const std::string slotText = r.slot > 0 ? fmt::format(" (job slot {})", r.slot) : "";

    if (hardware.empty())
        return software(allowed.empty() ? "no GPU EGL device: software rendering (llvmpipe)"
                                        : fmt::format("{} but no GPU EGL device: software "
                                                      "rendering (llvmpipe)",
                                                      from));
    if (allowed.empty()) {
        const int pick = hardware[static_cast<std::size_t>(r.slot) % hardware.size()];
        return {pick, false,
                fmt::format("GPU {} of {} in EGL order{}", r.slot % hardware.size(),
                            hardware.size(), slotText)};
    }
    const std::size_t k = static_cast<std::size_t>(r.slot) % allowed.size();
    const int target = allowed[k];
    if (cudaOrdinals)
        for (int i : hardware)
            if (devices[static_cast<std::size_t>(i)].cudaDevice == target)
                return {i, false,
                        fmt::format("CUDA device {} (EGL_CUDA_DEVICE_NV) from {}{}", target, from,
                                    slotText)};
    if (hardware.size() == allowed.size())
        return {hardware[k], false,
                fmt::format("GPU {} of the {} this node shows (EGL order) from {}{}", k,
                            hardware.size(), from, slotText)};
    if (!cudaOrdinals && target < static_cast<int>(hardware.size()))
        return {hardware[static_cast<std::size_t>(target)], false,
                fmt::format("GPU {} in EGL order from {}{}", target, from, slotText)};
    std::vector<int> have;
    for (int i : hardware)
        have.push_back(devices[static_cast<std::size_t>(i)].cudaDevice);
    throw Error(fmt::format(
        "{} asks for GPU {}, but the EGL devices are {} GPU(s){} (use "
        "--device N or VEIL_EGL_DEVICE)",
        from, target, hardware.size(),
        cudaOrdinals ? fmt::format(" with CUDA ordinals {}", fmt::join(have, ",")) : ""));
}

} // namespace veil::gpu
