#include "visfield/render/compare.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "visfield/core/error.hpp"

namespace vf {

ImageDifference compare_images(const Image& image, const Image& reference) {
  if (image.width != reference.width || image.height != reference.height)
    throw Error("compare: images of " + std::to_string(image.width) + "x" + std::to_string(image.height) + " and " +
                std::to_string(reference.width) + "x" + std::to_string(reference.height) + " pixels");
  ImageDifference d;
  double sum = 0.0;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double diff = static_cast<double>(image.pixels[i][c]) - reference.pixels[i][c];
      sum += diff * diff;
      d.max_abs = std::max(d.max_abs, std::fabs(diff));
    }
  }
  const double samples = 3.0 * static_cast<double>(image.pixels.size());
  d.rms = samples > 0.0 ? std::sqrt(sum / samples) : 0.0;
  d.psnr_db = d.rms > 0.0 ? -20.0 * std::log10(d.rms) : std::numeric_limits<double>::infinity();
  return d;
}

}  // namespace vf
