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
  std::vector<std::uint8_t> rgb(image.pixels.size() * 3);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = encode_srgb8(image.pixels[i][c]);
  std::string encoded;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (stbi_write_png_to_func(append, &encoded, image.width, image.height, 3, rgb.data(), image.width * 3) == 0)
    throw Error(path.string() + ": cannot encode PNG");
  write_file_bytes(path, encoded);
}

Image read_png(const std::filesystem::path& path) {
  int width = 0, height = 0, channels = 0;
  const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> data(
      stbi_load(path.c_str(), &width, &height, &channels, 3), &stbi_image_free);
  if (!data) throw Error(path.string() + ": malformed PNG: " + stbi_failure_reason());
  Image image(width, height);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = {decode_srgb8(data.get()[3 * i]), decode_srgb8(data.get()[3 * i + 1]),
                       decode_srgb8(data.get()[3 * i + 2])};
  return image;
}

}  // namespace io_detail
}  // namespace vf
