#include "visfield/io/image_io.hpp"

#include <string>

#include "file_checks.hpp"
#include "image_formats.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/atomic_file.hpp"

namespace vf {
namespace {

enum class ImageFormat { png, exr };

ImageFormat format_of(const std::filesystem::path& path) {
  const std::string ext = io_detail::lower_extension(path);
  if (ext == "png") return ImageFormat::png;
  if (ext == "exr") return ImageFormat::exr;
  throw Error(path.string() + ": unknown image format \"" + path.extension().string() + "\" (expected .png or .exr)");
}

}  // namespace

void write_image(const std::filesystem::path& path, const Image& image) {
  const ImageFormat format = format_of(path);
  if (image.width <= 0 || image.height <= 0)
    throw Error(path.string() + ": cannot write an empty image (" + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ")");
  if (image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw Error(path.string() + ": image has " + std::to_string(image.pixels.size()) + " pixels, expected " +
                std::to_string(image.width) + "x" + std::to_string(image.height));
  if (!image.alpha.empty() && image.alpha.size() != image.pixels.size())
    throw Error(path.string() + ": image has " + std::to_string(image.alpha.size()) + " alpha values for " +
                std::to_string(image.pixels.size()) + " pixels");
  write_atomically(path, [&](const std::filesystem::path& temp) {
    if (format == ImageFormat::png) io_detail::write_png(temp, image);
    else io_detail::write_exr(temp, image);
  });
}

Image read_image(const std::filesystem::path& path) {
  const ImageFormat format = format_of(path);
  io_detail::require_readable_file(path);
  return format == ImageFormat::png ? io_detail::read_png(path) : io_detail::read_exr(path);
}

}  // namespace vf
