#pragma once
/// \file Device memory owned by RAII objects: a byte buffer and a typed array over it. Errors are
/// vf::Error with CUDA's message. Move-only; not thread-safe to move while in use.

#include <cstddef>
#include <span>
#include <vector>

namespace vf::cuda {

/// `bytes` bytes of device memory (cudaMalloc), freed by the destructor.
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  /// Allocates `bytes` bytes (none for 0). Throws vf::MemoryRefused, before allocating, for more than
  /// the device has free, and vf::Error when the device refuses.
  explicit DeviceBuffer(std::size_t bytes);
  DeviceBuffer(DeviceBuffer&& other) noexcept;
  DeviceBuffer& operator=(DeviceBuffer&& other) noexcept;
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  ~DeviceBuffer();

  /// The device address (null when empty).
  void* data() const { return data_; }
  /// Bytes held.
  std::size_t bytes() const { return bytes_; }
  /// Copies `bytes` bytes from host memory to offset `offset` (synchronous). Throws vf::Error past the end.
  void upload(const void* host, std::size_t bytes, std::size_t offset = 0);
  /// Copies `bytes` bytes from offset `offset` to host memory (synchronous). Throws vf::Error past the end.
  void download(void* host, std::size_t bytes, std::size_t offset = 0) const;

 private:
  void* data_ = nullptr;
  std::size_t bytes_ = 0;
};

/// `size` values of a trivially copyable T in device memory.
template <class T>
class DeviceArray {
 public:
  DeviceArray() = default;
  /// Room for `size` values, uninitialised.
  explicit DeviceArray(std::size_t size) : buffer_(size * sizeof(T)), size_(size) {}
  /// A device copy of `host`.
  static DeviceArray from(std::span<const T> host) {
    DeviceArray a(host.size());
    a.buffer_.upload(host.data(), host.size_bytes());
    return a;
  }
  /// The values copied to the host.
  std::vector<T> to_host() const {
    std::vector<T> out(size_);
    buffer_.download(out.data(), size_ * sizeof(T));
    return out;
  }
  /// The device address.
  T* data() const { return static_cast<T*>(buffer_.data()); }
  /// Number of values.
  std::size_t size() const { return size_; }
  /// Bytes held.
  std::size_t bytes() const { return buffer_.bytes(); }

 private:
  DeviceBuffer buffer_;
  std::size_t size_ = 0;
};

}  // namespace vf::cuda
