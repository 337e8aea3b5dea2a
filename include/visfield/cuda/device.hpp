#pragma once
/// \file The CUDA device visfield runs on (device 0): whether there is one, its name and peaks.
/// Only in builds with VISFIELD_CUDA=ON (the library visfield::cuda).

#include <cstddef>
#include <functional>
#include <string>

#include "visfield/gpu/roofline.hpp"

namespace vf::cuda {

/// What the kernels run on.
struct DeviceInfo {
  std::string name;              ///< "NVIDIA H100 80GB HBM3".
  int sm_count = 0;              ///< Streaming multiprocessors.
  int major = 0, minor = 0;      ///< Compute capability (9.0 for an H100).
  double clock_hz = 0.0;         ///< Peak SM clock.
  std::size_t memory_bytes = 0;  ///< Global memory.
  gpu::DevicePeaks peaks;        ///< DRAM bandwidth, L2 size, FP32 operations a second (128 lanes an SM, unfused).
};

/// Whether a CUDA device is usable: cudaGetDeviceCount succeeds with at least one device. Never
/// throws; cheap after the first call.
bool device_available();

/// Device 0's properties. Throws vf::Error("no CUDA device found") when there is none.
DeviceInfo device_info();

/// Throws vf::Error("no CUDA device found") unless device_available().
void require_device();

/// Device milliseconds of the kernels that `job` launches on this thread: CUDA events recorded
/// around each launch alone (memsets, copies and host work left out), summed. Rethrows what `job`
/// throws.
double kernel_ms(const std::function<void()>& job);

/// Throws vf::Error("CUDA: <what>: <CUDA's error string>") when `status` (a cudaError_t) is not
/// cudaSuccess.
void check(int status, const char* what);

}  // namespace vf::cuda
