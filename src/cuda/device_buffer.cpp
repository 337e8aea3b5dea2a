#include "visfield/cuda/device_buffer.hpp"

#include <cuda_runtime_api.h>

#include <string>
#include <utility>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/cuda/device.hpp"

namespace vf::cuda {

DeviceBuffer::DeviceBuffer(std::size_t bytes) {
  if (bytes == 0) return;
  require_device();
  // Refused before allocating, as host builds are: beyond what the device has free.
  std::size_t free_bytes = 0, total_bytes = 0;
  if (cudaMemGetInfo(&free_bytes, &total_bytes) == cudaSuccess && bytes > free_bytes)
    throw MemoryRefused("CUDA: the upload would need about " + format_bytes(static_cast<double>(bytes)) + ", more than the " +
                        format_bytes(static_cast<double>(free_bytes)) + " free on the device");
  const cudaError_t status = cudaMalloc(&data_, bytes);
  if (status != cudaSuccess) {
    data_ = nullptr;
    throw Error("CUDA: cannot allocate " + std::to_string(bytes) + " bytes of device memory: " + cudaGetErrorString(status));
  }
  bytes_ = bytes;
}

DeviceBuffer::DeviceBuffer(DeviceBuffer&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)), bytes_(std::exchange(other.bytes_, 0)) {}

DeviceBuffer& DeviceBuffer::operator=(DeviceBuffer&& other) noexcept {
  if (this != &other) {
    if (data_) cudaFree(data_);
    data_ = std::exchange(other.data_, nullptr);
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

DeviceBuffer::~DeviceBuffer() {
  if (data_) cudaFree(data_);  // a destructor cannot report; cudaFree fails only on a broken context
}

void DeviceBuffer::upload(const void* host, std::size_t bytes, std::size_t offset) {
  if (bytes == 0) return;
  if (offset > bytes_ || bytes > bytes_ - offset) throw Error("CUDA: upload past the end of a device buffer");
  check(cudaMemcpy(static_cast<char*>(data_) + offset, host, bytes, cudaMemcpyHostToDevice), "cudaMemcpy to the device");
}

void DeviceBuffer::download(void* host, std::size_t bytes, std::size_t offset) const {
  if (bytes == 0) return;
  if (offset > bytes_ || bytes > bytes_ - offset) throw Error("CUDA: download past the end of a device buffer");
  check(cudaMemcpy(host, static_cast<const char*>(data_) + offset, bytes, cudaMemcpyDeviceToHost), "cudaMemcpy to the host");
}

}  // namespace vf::cuda
