#include "visfield/cuda/device.hpp"

#include <cuda_runtime_api.h>

#include <string>
#include <utility>

#include "visfield/core/error.hpp"

namespace vf::cuda {
namespace {

thread_local double* g_kernel_total = nullptr;  // the innermost kernel_ms() of this thread, if any

}  // namespace

namespace detail {

bool kernel_clock_running() { return g_kernel_total != nullptr; }
void add_kernel_ms(double ms) { *g_kernel_total += ms; }

}  // namespace detail

double kernel_ms(const std::function<void()>& job) {
  double total = 0.0;
  struct Restore {
    double* outer;
    ~Restore() { g_kernel_total = outer; }
  } restore{std::exchange(g_kernel_total, &total)};
  job();
  if (restore.outer) *restore.outer += total;
  return total;
}

void check(int status, const char* what) {
  if (status == cudaSuccess) return;
  throw Error(std::string("CUDA: ") + what + ": " + cudaGetErrorString(static_cast<cudaError_t>(status)));
}

bool device_available() {
  static const bool available = [] {
    int count = 0;
    return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
  }();
  return available;
}

void require_device() {
  if (!device_available()) throw Error("no CUDA device found");
}

DeviceInfo device_info() {
  require_device();
  cudaDeviceProp p{};
  check(cudaGetDeviceProperties(&p, 0), "cudaGetDeviceProperties");
  int clock_khz = 0, memory_khz = 0, bus_bits = 0;
  check(cudaDeviceGetAttribute(&clock_khz, cudaDevAttrClockRate, 0), "cudaDeviceGetAttribute");
  check(cudaDeviceGetAttribute(&memory_khz, cudaDevAttrMemoryClockRate, 0), "cudaDeviceGetAttribute");
  check(cudaDeviceGetAttribute(&bus_bits, cudaDevAttrGlobalMemoryBusWidth, 0), "cudaDeviceGetAttribute");
  DeviceInfo info;
  info.name = p.name;
  info.sm_count = p.multiProcessorCount;
  info.major = p.major;
  info.minor = p.minor;
  info.clock_hz = 1e3 * clock_khz;
  info.memory_bytes = p.totalGlobalMem;
  // Double data rate: two transfers a memory clock over the whole bus.
  info.peaks.dram_bytes_per_s = 2.0 * 1e3 * memory_khz * (bus_bits / 8.0);
  info.peaks.l2_bytes = static_cast<double>(p.l2CacheSize);
  // 128 FP32 lanes an SM on sm_80/sm_90 (64 below); one unfused operation a lane a cycle.
  info.peaks.flops_per_s = info.sm_count * (p.major >= 8 ? 128.0 : 64.0) * info.clock_hz;
  return info;
}

}  // namespace vf::cuda
