// Which EGL device a headless context renders on. On a cluster node the scheduler says which
// GPUs a task may use (CUDA_VISIBLE_DEVICES, or Slurm's SLURM_STEP_GPUS / SLURM_JOB_GPUS);
// EGL enumerates the node's devices in an order of its own, so the choice matches them by the
// CUDA ordinal the NVIDIA driver reports per EGL device (EGL_NV_device_cuda's
// EGL_CUDA_DEVICE_NV, read through EGL_EXT_device_query), else by the order of the hardware
// devices. This part is pure (no EGL calls) so it is tested on recorded values.
#pragma once

#include <string>
#include <vector>

namespace veil::gpu {

// What EGL says about one device.
struct EglDeviceFacts {
    int cudaDevice = -1;   // EGL_CUDA_DEVICE_NV, -1 when the driver does not report it
    bool software = false; // EGL_MESA_device_software (llvmpipe)
};

// What the command line and the environment ask for.
struct DeviceRequest {
    int index = -1;        // --device or VEIL_EGL_DEVICE; -1: none
    std::string indexFrom; // "--device" or "VEIL_EGL_DEVICE"
    bool cudaVisibleSet = false;
    std::string cudaVisible;   // CUDA_VISIBLE_DEVICES
    std::string slurmStepGpus; // SLURM_STEP_GPUS
    std::string slurmJobGpus;  // SLURM_JOB_GPUS
    int slot = 0;              // k of `veil regress --jobs`: the k-th allowed GPU, mod their count
};

// The request from `deviceOption` (>= 0: --device) and the variables above plus VEIL_EGL_DEVICE
// and VEIL_GPU_SLOT. A malformed VEIL_EGL_DEVICE or VEIL_GPU_SLOT is a veil::Error naming it.
DeviceRequest deviceRequestFromEnvironment(int deviceOption);

struct DeviceChoice {
    int index = -1;      // into the EGL device list
    bool strict = false; // an explicit index: no other device is tried when it fails
    std::string why;     // for the log: what chose it
};

// The device for `request` among `devices`:
// - an explicit index (--device, VEIL_EGL_DEVICE) wins;
// - else the allowed GPUs are CUDA_VISIBLE_DEVICES (integers; UUIDs cannot be matched to EGL
//   devices and fall through), else SLURM_STEP_GPUS, else SLURM_JOB_GPUS; the slot picks one,
//   and the EGL device with that CUDA ordinal is taken; when none has it but the node shows
//   exactly as many GPUs as were allowed (a device cgroup hides the others and the numbers
//   are the host's), the slot picks among the shown GPUs in EGL order; without CUDA ordinals
//   the number is taken as the position among the hardware devices;
// - else the slot picks among all hardware devices;
// - a node with no hardware device (or CUDA_VISIBLE_DEVICES empty or -1) renders on the first
//   software device, and `why` says so.
// Errors (an index past the list, an allowed GPU that is not there) are veil::Error.
DeviceChoice chooseDevice(const std::vector<EglDeviceFacts>& devices, const DeviceRequest& request);

} // namespace veil::gpu
