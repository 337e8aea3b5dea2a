#include "bench_rays.hpp"

#include <cmath>
#include <string>

#include "visfield/core/error.hpp"

namespace vf::bench {

namespace {

constexpr int kMaxImageSide = 65536;

}  // namespace

std::vector<Ray> take_evenly(const std::vector<Ray>& rays, std::size_t count) {
  // floor(i * size / count) as i * quotient + floor(i * remainder / count): no overflow while
  // count^2 fits in 64 bits, which the --count limit guarantees.
  const std::size_t quotient = rays.size() / count, remainder = rays.size() % count;
  std::vector<Ray> picked(count);
  for (std::size_t i = 0; i < count; ++i) picked[i] = rays[i * quotient + i * remainder / count];
  return picked;
}

std::vector<Ray> rays_for_count(const Camera& camera, std::optional<std::size_t> count,
                                const std::function<std::vector<Ray>(const Camera&)>& generate, std::size_t rays_per_pixel) {
  Camera scaled = camera;
  const double most = static_cast<double>(camera.width) * camera.height * static_cast<double>(std::max<std::size_t>(rays_per_pixel, 1));
  if (count && most > 4.0 * static_cast<double>(*count)) {
    // Far more rays than asked for: a smaller image (same aspect) whose every pixel could give its
    // rays_per_pixel rays, so that AO rays come whole from each point and no huge set is made.
    const double factor = std::sqrt(1.05 * static_cast<double>(*count) / most);
    scaled.width = std::max(1, static_cast<int>(std::lround(camera.width * factor)));
    scaled.height = std::max(1, static_cast<int>(std::lround(camera.height * factor)));
  }
  std::vector<Ray> rays = generate(scaled);
  if (rays.empty()) {
    throw Error("no rays to trace: the camera at " + std::to_string(camera.width) + "x" +
                std::to_string(camera.height) + " sees no geometry");
  }
  if (!count) return rays;
  while (rays.size() < *count) {
    // Each pass grows the image by the missing factor (plus 5% for the pixels that see nothing),
    // so a scene seen by a fixed fraction of the pixels needs one pass.
    const double factor = std::sqrt(static_cast<double>(*count) / static_cast<double>(rays.size())) * 1.05;
    const double width = std::ceil(scaled.width * factor), height = std::ceil(scaled.height * factor);
    if (width > kMaxImageSide || height > kMaxImageSide) {
      throw Error(std::to_string(*count) + " rays would need an image over " + std::to_string(kMaxImageSide) +
                  " pixels a side; ask for fewer (--count)");
    }
    scaled.width = static_cast<int>(width);
    scaled.height = static_cast<int>(height);
    rays = generate(scaled);
  }
  return take_evenly(rays, *count);
}

}  // namespace vf::bench
