#include <stb_image.h>
#include <stb_image_write.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "image_formats.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/io/image_io.hpp"

namespace vf {

std::uint8_t encode_srgb8(float linear) {
  const float v = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;  // NaN fails both tests: 0
  const float encoded = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<std::uint8_t>(std::lround(encoded * 255.0f));
}

float decode_srgb8(std::uint8_t code) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[i] = static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table[code];
}

namespace io_detail {

void write_png(const std::filesystem::path& path, const Image& image) {
  const int channels = image.alpha.empty() ? 3 : 4;
  std::vector<std::uint8_t> bytes(image.pixels.size() * static_cast<std::size_t>(channels));
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) bytes[channels * i + c] = encode_srgb8(image.pixels[i][c]);
    if (channels == 4) {
      const float a = image.alpha[i] > 0.0f ? (image.alpha[i] < 1.0f ? image.alpha[i] : 1.0f) : 0.0f;  // alpha is linear
      bytes[4 * i + 3] = static_cast<std::uint8_t>(std::lround(a * 255.0f));
    }
  }
  std::string encoded;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (stbi_write_png_to_func(append, &encoded, image.width, image.height, channels, bytes.data(), image.width * channels) == 0)
    throw Error(path.string() + ": cannot encode PNG");
  write_file_bytes(path, encoded);
}

Image read_png(const std::filesystem::path& path) {
  int width = 0, height = 0, channels = 0;
  if (!stbi_info(path.c_str(), &width, &height, &channels)) throw Error(path.string() + ": malformed PNG: " + stbi_failure_reason());
  const bool with_alpha = channels == 2 || channels == 4;  // grey + alpha, RGBA
  const int stride = with_alpha ? 4 : 3;
  const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> data(
      stbi_load(path.c_str(), &width, &height, &channels, stride), &stbi_image_free);
  if (!data) throw Error(path.string() + ": malformed PNG: " + stbi_failure_reason());
  Image image(width, height);
  if (with_alpha) image.alpha.resize(image.pixels.size());
  const stbi_uc* p = data.get();
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    image.pixels[i] = {decode_srgb8(p[stride * i]), decode_srgb8(p[stride * i + 1]), decode_srgb8(p[stride * i + 2])};
    if (with_alpha) image.alpha[i] = static_cast<float>(p[stride * i + 3]) / 255.0f;
  }
  return image;
}

}  // namespace io_detail
}  // namespace vf
