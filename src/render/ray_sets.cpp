#include "visfield/render/ray_sets.hpp"

#include <cmath>
#include <string>

#include <tbb/blocked_range.h>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/core/parallel.hpp"

namespace vf {
namespace {

constexpr int kMaxImageSide = 65536;

// Refuses, before allocating, a ray set larger than the allocation budget.
void check_fits_in_memory(std::size_t count, const char* what) {
  require_memory(static_cast<double>(count) * sizeof(Ray), std::string(what) + ": " + std::to_string(count) + " rays");
}

// Start index of each hit pixel's rays in the output, and the total; pixels are taken in order.
std::vector<std::size_t> hit_offsets(std::span<const Ray> primary, std::span<const Hit> hits, std::size_t rays_per_hit,
                                     std::size_t& total) {
  if (primary.size() != hits.size())
    throw Error("ray sets: " + std::to_string(primary.size()) + " primary rays but " + std::to_string(hits.size()) + " hits");
  std::vector<std::size_t> offsets(hits.size());
  total = 0;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    offsets[i] = total;
    if (hits[i]) total += rays_per_hit;
  }
  return offsets;
}

}  // namespace

std::vector<Ray> make_primary_rays(const Scene& /*scene*/, const Camera& camera) {
  const PinholeCamera pinhole(camera);
  const auto width = static_cast<std::size_t>(pinhole.width());
  const std::size_t count = width * static_cast<std::size_t>(pinhole.height());
  check_fits_in_memory(count, "primary rays");
  std::vector<Ray> rays(count);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      rays[i] = pixel_center_ray(pinhole, static_cast<int>(i % width), static_cast<int>(i / width));
  });
  return rays;
}

namespace {

// Calls f(pixel, rng, point) in parallel for every pixel whose primary ray hit, with the pixel's
// random stream Rng(seed, pixel, 0) and the surface point secondary rays leave from.
template <class F>
void for_each_surface_point(const Scene& scene, std::span<const Ray> primary, std::span<const Hit> hits,
                            std::uint64_t seed, F&& f) {
  const SurfaceSpawner spawner(scene);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, hits.size(), 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t pixel = range.begin(); pixel != range.end(); ++pixel) {
      if (!hits[pixel]) continue;
      Rng rng(seed, pixel, 0);
      f(pixel, rng, spawner.surface_point(primary[pixel], hits[pixel]));
    }
  });
}

}  // namespace

std::vector<Ray> ao_rays_from_hits(const Scene& scene, std::span<const Ray> primary, std::span<const Hit> hits,
                                   int rays_per_hit, float max_distance, std::uint64_t seed) {
  if (rays_per_hit < 1) throw Error("ao rays: rays per hit must be at least 1, got " + std::to_string(rays_per_hit));
  if (!(max_distance > 0.0f)) throw Error("ao rays: max_distance must be positive, got " + std::to_string(max_distance));
  std::size_t total = 0;
  const std::vector<std::size_t> offsets = hit_offsets(primary, hits, static_cast<std::size_t>(rays_per_hit), total);
  check_fits_in_memory(total, "ao rays");
  std::vector<Ray> rays(total);
  // The same stream and the same calls as render_ao's first (only) sample of each pixel.
  for_each_surface_point(scene, primary, hits, seed, [&](std::size_t pixel, Rng& rng, const SurfacePoint& point) {
    for (int k = 0; k < rays_per_hit; ++k) rays[offsets[pixel] + static_cast<std::size_t>(k)] = ao_ray(point, rng, max_distance);
  });
  return rays;
}

std::vector<Ray> psf_ao_rays_from_hits(const Scene& scene, std::span<const Ray> primary, std::span<const Hit> hits,
                                       const DirectionLines& lines, float max_distance) {
  if (!(max_distance > 0.0f)) throw Error("ao rays: max_distance must be positive, got " + std::to_string(max_distance));
  std::size_t total = 0;
  const std::vector<std::size_t> offsets = hit_offsets(primary, hits, lines.size(), total);
  check_fits_in_memory(total, "ao rays");
  std::vector<Ray> rays(total);
  for_each_surface_point(scene, primary, hits, 0, [&](std::size_t pixel, Rng&, const SurfacePoint& point) {
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const Vec3f& w = lines.direction(k);
      rays[offsets[pixel] + k] = Ray{point.position, dot(point.normal, w) >= 0.0f ? w : -w, 0.0f, max_distance};
    }
  });
  return rays;
}

std::vector<Ray> shadow_rays_from_hits(const Scene& scene, std::span<const Ray> primary, std::span<const Hit> hits,
                                       std::uint64_t seed) {
  std::size_t total = 0;
  const std::vector<std::size_t> offsets = hit_offsets(primary, hits, 1, total);
  const LightTargets lights(scene);
  std::vector<Ray> rays(total);
  for_each_surface_point(scene, primary, hits, seed, [&](std::size_t pixel, Rng& rng, const SurfacePoint& point) {
    rays[offsets[pixel]] = shadow_ray(point, lights.sample(point.position, rng));
  });
  return rays;
}

std::vector<Ray> make_random_rays(const Bounds3f& bounds, std::size_t count, std::uint64_t seed) {
  if (bounds.empty()) throw Error("random rays: the scene bounds are empty");
  check_fits_in_memory(count, "random rays");
  const Vec3f center = bounds.center();
  const float half_diagonal = 0.5f * length(bounds.extent());
  const float radius = half_diagonal > 0.0f ? half_diagonal : 1.0f;  // a single point gets a unit sphere
  std::vector<Ray> rays(count);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      Rng rng(seed, i);
      Vec3f a, b;
      float distance = 0.0f;
      do {  // two coincident points (probability ~2^-40) would give no direction: draw again
        const float s0 = rng.uniform(), t0 = rng.uniform(), s1 = rng.uniform(), t1 = rng.uniform();
        a = center + uniform_sphere(s0, t0) * radius;
        b = center + uniform_sphere(s1, t1) * radius;
        distance = length(b - a);
      } while (!(distance > 1e-6f * radius));
      rays[i] = Ray{a, (b - a) * (1.0f / distance), 0.0f, distance};
    }
  });
  return rays;
}

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

}  // namespace vf
