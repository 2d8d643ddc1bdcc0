// gpu::chooseDevice on the EGL device lists and scheduler variables of the node layouts a
// task meets: values as Slurm's gres/gpu plugin sets them (CUDA_VISIBLE_DEVICES and
// SLURM_JOB_GPUS / SLURM_STEP_GPUS, with and without a device cgroup) and as the NVIDIA and
// Mesa EGL drivers list devices (NVIDIA GPUs with EGL_CUDA_DEVICE_NV, then llvmpipe).
#include "base/error.h"
#include "gpu/device_choice.h"

#include <gtest/gtest.h>

namespace veil::test {

namespace {

using gpu::EglDeviceFacts;

// A node whose EGL order is not CUDA's: EGL devices 0..3 are CUDA 1, 0, 3, 2; 4 is llvmpipe.
const std::vector<EglDeviceFacts> kFourGpus{
    {1, false}, {0, false}, {3, false}, {2, false}, {-1, true}};
const std::vector<EglDeviceFacts> kLlvmpipe{{-1, true}};

gpu::DeviceRequest cuda(const std::string& visible, int slot = 0) {
    gpu::DeviceRequest r;
    r.cudaVisibleSet = true;
    r.cudaVisible = visible;
    r.slot = slot;
    return r;
}

} // namespace

TEST(DeviceChoiceTest, CudaVisibleDevicesIsMatchedByCudaOrdinal) {
    EXPECT_EQ(gpu::chooseDevice(kFourGpus, cuda("2")).index, 3);
    EXPECT_EQ(gpu::chooseDevice(kFourGpus, cuda("0")).index, 1);
    const gpu::DeviceChoice c = gpu::chooseDevice(kFourGpus, cuda("3"));
    EXPECT_EQ(c.index, 2);
    EXPECT_NE(c.why.find("CUDA device 3 (EGL_CUDA_DEVICE_NV) from CUDA_VISIBLE_DEVICES=3"),
              std::string::npos)
        << c.why;
    // UUIDs cannot be matched: SLURM_JOB_GPUS (host numbers) is used.
    gpu::DeviceRequest r = cuda("GPU-8d2c5e3a-1f7b-4c1e-9a0e-3b5d7c9e1f20");
    r.slurmJobGpus = "2";
    EXPECT_EQ(gpu::chooseDevice(kFourGpus, r).index, 3);
}

TEST(DeviceChoiceTest, SlurmVariablesWithoutCudaVisibleDevices) {
    gpu::DeviceRequest r;
    r.slurmJobGpus = "0,1,2,3";
    r.slurmStepGpus = "1";
    EXPECT_EQ(gpu::chooseDevice(kFourGpus, r).index, 0); // the step's GPU, CUDA 1
    r.slurmStepGpus.clear();
    r.slurmJobGpus = "3";
    EXPECT_EQ(gpu::chooseDevice(kFourGpus, r).index, 2);
}

TEST(DeviceChoiceTest, DeviceCgroupShowsOnlyTheAllocatedGpus) {
    // ConstrainDevices=yes: the task sees one GPU, CUDA numbers it 0, Slurm names host GPU 2.
    const std::vector<EglDeviceFacts> shown{{0, false}, {-1, true}};
    gpu::DeviceRequest r = cuda("0");
    r.slurmJobGpus = "2";
    EXPECT_EQ(gpu::chooseDevice(shown, r).index, 0);
    // Only the host numbers known (no CUDA_VISIBLE_DEVICES): as many GPUs shown as allowed.
    gpu::DeviceRequest host;
    host.slurmStepGpus = "2,3";
    host.slot = 1;
    const std::vector<EglDeviceFacts> two{{0, false}, {1, false}, {-1, true}};
    const gpu::DeviceChoice c = gpu::chooseDevice(two, host);
    EXPECT_EQ(c.index, 1);
    EXPECT_NE(c.why.find("this node shows"), std::string::npos) << c.why;
}

TEST(DeviceChoiceTest, WithoutCudaOrdinalsTheHardwareOrderIsUsed) {
    const std::vector<EglDeviceFacts> mesa{{-1, false}, {-1, false}, {-1, false}, {-1, true}};
    gpu::DeviceRequest r;
    r.slurmJobGpus = "1";
    EXPECT_EQ(gpu::chooseDevice(mesa, r).index, 1);
}

TEST(DeviceChoiceTest, JobSlotsGoRoundTheAllowedGpus) {
    // `veil regress --jobs 4` on a node with 2 GPUs: jobs 0..3 on GPUs 0, 1, 0, 1.
    const std::vector<EglDeviceFacts> two{{0, false}, {1, false}, {-1, true}};
    for (int k = 0; k < 4; ++k) {
        gpu::DeviceRequest r;
        r.slot = k;
        EXPECT_EQ(gpu::chooseDevice(two, r).index, k % 2) << k;
    }
    // Within what CUDA_VISIBLE_DEVICES allows: 1 and 3 of four.
    const int expected[] = {0, 2, 0}; // EGL devices of CUDA 1, 3, 1
    for (int k = 0; k < 3; ++k)
        EXPECT_EQ(gpu::chooseDevice(kFourGpus, cuda("1,3", k)).index, expected[k]) << k;
}

TEST(DeviceChoiceTest, NoGpuMeansLlvmpipeAndSaysSo) {
    const gpu::DeviceChoice c = gpu::chooseDevice(kLlvmpipe, {});
    EXPECT_EQ(c.index, 0);
    EXPECT_NE(c.why.find("software rendering (llvmpipe)"), std::string::npos) << c.why;
    EXPECT_EQ(gpu::chooseDevice(kFourGpus, cuda("")).index, 4);
    EXPECT_EQ(gpu::chooseDevice(kFourGpus, cuda("-1")).index, 4);
    EXPECT_NE(gpu::chooseDevice(kLlvmpipe, cuda("0")).why.find("but no GPU EGL device"),
              std::string::npos);
}

TEST(DeviceChoiceTest, ExplicitIndexWinsAndIsChecked) {
    gpu::DeviceRequest r = cuda("2");
    r.index = 4;
    r.indexFrom = "--device";
    const gpu::DeviceChoice c = gpu::chooseDevice(kFourGpus, r);
    EXPECT_EQ(c.index, 4);
    EXPECT_TRUE(c.strict);
    r.index = 5;
    try {
        gpu::chooseDevice(kFourGpus, r);
        FAIL() << "device 5 of 5 accepted";
    } catch (const Error& e) {
        EXPECT_NE(
            std::string(e.what()).find("EGL device 5 (from --device): only 5 EGL device(s) exist"),
            std::string::npos)
            << e.what();
    }
    // A GPU that is not there is an error naming the variable, not another GPU.
    try {
        gpu::chooseDevice(kFourGpus, cuda("7"));
        FAIL() << "CUDA device 7 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("CUDA_VISIBLE_DEVICES=7 asks for GPU 7"),
                  std::string::npos)
            << e.what();
    }
}

} // namespace veil::test
