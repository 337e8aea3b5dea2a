#pragma once
// The fuzz targets' view of their input: bytes read front to back, and zeros past its end, so that
// every input, however short, describes a complete case.

#include <cstdint>
#include <cstring>

namespace vf::fuzz {

/// Reads a fuzz input front to back; past its end every read gives zeros.
class InputReader {
 public:
  InputReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  /// Whether every byte has been read.
  bool done() const { return pos_ >= size_; }
  /// The next byte.
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  /// The next two bytes, little-endian.
  std::uint16_t u16() { return static_cast<std::uint16_t>(byte() | (byte() << 8)); }
  /// The next four bytes, little-endian.
  std::uint32_t u32() { return static_cast<std::uint32_t>(u16()) | (static_cast<std::uint32_t>(u16()) << 16); }
  /// The next four bytes as a float's bits: any value, NaN, infinities and denormals included.
  float bits() {
    const std::uint32_t word = u32();
    float f;
    std::memcpy(&f, &word, sizeof f);
    return f;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
};

}  // namespace vf::fuzz
