#include "visfield/select/decision.hpp"

#include <cmath>
#include <string>

#include "visfield/accel/kdtree.hpp"
#include "visfield/core/error.hpp"
#include "visfield/select/timing.hpp"
#include "visfield/select/workload.hpp"

namespace vf {

void validate_select_options(const SelectOptions& options) {
  if (options.sample_rays < 5 || options.sample_rays > 1'000'000)
    throw Error("select: sample rays must be in 5..1000000, got " + std::to_string(options.sample_rays));
  if (!(options.epsilon >= 0.0) || !std::isfinite(options.epsilon))
    throw Error("select: epsilon must be a finite number >= 0, got " + std::to_string(options.epsilon));
  if (options.path_bounces < 0 || options.path_bounces > 16)
    throw Error("select: path bounces must be in 0..16, got " + std::to_string(options.path_bounces));
}

Selection select_structure(const Scene& scene, const TriangleSet& triangles, std::uint64_t rays,
                           const Calibration& calibration, RayKind kind, const SelectOptions& options) {
  validate_select_options(options);
  if (triangles.size() == 0) throw Error("select: the scene has no non-degenerate triangles");
  Selection s;
  s.kind = kind;
  s.rays = rays;
  s.triangles = triangles.size();

  // Step 1: build the grid (timed).
  std::optional<UniformGrid> grid(UniformGrid::build(triangles));
  s.grid_build_ms = grid->stats().build_ms;
  s.grid_resolution = grid->resolution();
  s.grid_memory_bytes = grid->stats().memory_bytes;
  s.grid_statistics = compute_grid_statistics(*grid);

  // Step 2: t_R^G from a sample of representative rays.
  const int threads = threads_in_force();
  const SampleTiming sample =
      time_sample(kind, *grid, scene, triangles, options.sample_rays, options.seed, options.path_bounces, threads);
  s.sample_count = sample.count;
  s.grid_ray_us = sample.query_us;

  // Steps 3-6: the hierarchy's costs from the calibration (eqs. 7, 8), then R_C.
  s.tree_build_ms = estimated_tree_build_ms(calibration.constants, s.triangles);
  // Per-ray times are single-thread times over the thread count: rescale the calibration's to ours.
  const double thread_ratio = calibration.machine.threads > 0 ? static_cast<double>(calibration.machine.threads) / threads : 1.0;
  s.tree_ray_us = estimated_tree_ray_us(calibration.constants, kind, s.triangles) * thread_ratio;
  s.critical_rays = estimated_critical_rays(s.tree_build_ms, s.grid_ray_us, s.tree_ray_us, options.epsilon);
  const double r = static_cast<double>(rays);
  s.grid_total_ms = r * s.grid_ray_us / 1000.0;
  s.tree_total_ms = s.tree_build_ms + r * s.tree_ray_us / 1000.0;

  // Steps 7-8.
  s.structure = grid_wins(r, s.critical_rays) ? UniformGrid::name() : KdTree::name();
  s.grid = std::move(grid);
  return s;
}

}  // namespace vf
