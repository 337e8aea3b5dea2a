#pragma once
/// \file Small helpers the GPU bench and figures share: printf-style formatting of one to four
/// numbers, rays over milliseconds as G rays/s, and the CPU's side of the kernels' counts (the
/// kernels' AO rays made on the host by the same header, occlusion flags counted per point).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "visfield/core/parallel.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/text.hpp"
#include "visfield/cuda/kernels.hpp"
#include "visfield/gpu/ray_generation.hpp"

namespace vf::bench {

/// `rays` in `ms` milliseconds as G rays per second (0 when no time was measured).
inline double grays(std::size_t rays, double ms) { return ms > 0.0 ? static_cast<double>(rays) / (ms * 1e-3) * 1e-9 : 0.0; }

/// The AO rays cuda::ambient_occlusion traces for `points` under `p`, point-major (rays_per_point each).
inline std::vector<Ray> kernel_ao_rays(const std::vector<gpu::SurfaceFrame>& points, const cuda::AoParams& p) {
  const std::size_t k = static_cast<std::size_t>(p.rays_per_point);
  std::vector<Ray> rays(points.size() * k);
  vf::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
    for (std::size_t j = 0; j < k; ++j) rays[i * k + j] = gpu::ao_ray(points[i], p.seed, i, j, p.max_distance);
  });
  return rays;
}

/// For each run of `per_group` consecutive flags, how many are 0 (the rays that reach their end): the
/// kernels' AO and soft-shadow counts from the CPU's occlusion answers.
inline std::vector<std::uint32_t> open_counts(std::span<const std::uint8_t> occluded, std::size_t per_group) {
  std::vector<std::uint32_t> open(occluded.size() / per_group, 0);
  for (std::size_t r = 0; r < occluded.size(); ++r) open[r / per_group] += occluded[r] ? 0 : 1;
  return open;
}

}  // namespace vf::bench
