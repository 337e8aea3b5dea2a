#pragma once
/// \file The decision algorithm (section 3): build the uniform grid, time a few hundred sample rays
/// through it, estimate the SAH kd-tree's build and per-ray cost from the calibration, compute the
/// critical ray count R_C and keep the grid when the workload has fewer rays.

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "visfield/accel/grid_stats.hpp"
#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/select/critical_rays.hpp"

namespace vf {

/// Parameters of the decision.
struct SelectOptions {
  std::uint64_t sample_rays = 500;   ///< S, sample rays traced through the grid (sample_query_us); 100..1000 in the paper (5..1e6 accepted).
  double epsilon = kCriticalEpsilon; ///< The paper's epsilon (>= 0).
  int path_bounces = 2;              ///< Diffuse bounces of path-tracing sample rays (0..16).
  std::uint64_t seed = 1;            ///< Seed of the sample rays.
};

/// Everything the decision computed. Times in milliseconds (builds) and microseconds per ray.
struct Selection {
  std::string structure;                 ///< "grid" or "kdtree" (the --accel names).
  RayKind kind = RayKind::path;          ///< Kind of the sample rays.
  std::uint64_t rays = 0;                ///< R, the workload's ray count.
  std::uint64_t triangles = 0;           ///< N.
  std::array<int, 3> grid_resolution{};  ///< Grid cells per axis.
  std::uint64_t grid_memory_bytes = 0;   ///< Bytes held by the grid.
  GridStatistics grid_statistics;        ///< The paper's statistics of the grid.
  double grid_build_ms = 0.0;            ///< T_B^G, measured (one build).
  std::uint64_t sample_count = 0;        ///< S, sample rays timed.
  double grid_ray_us = 0.0;              ///< t_R^G, measured on the sample (sample_query_us).
  double tree_build_ms = 0.0;            ///< T_B^H, estimated by eq. 7 (for the calibration's thread count).
  double tree_ray_us = 0.0;              ///< t_R^H, estimated by eq. 8 (rescaled from the calibration's thread count to ours).
  double critical_rays = 0.0;            ///< R_C (+infinity when the grid is never slower per ray).
  double grid_total_ms = 0.0;            ///< Estimated time to trace R rays with the grid already built.
  double tree_total_ms = 0.0;            ///< Estimated time to build the kd-tree and trace R rays with it.
  std::optional<UniformGrid> grid;       ///< The grid built for the decision: a caller that keeps the grid uses this one.
};

/// Throws vf::Error naming the bad setting unless the options are in their documented ranges.
void validate_select_options(const SelectOptions& options);

/// Runs the decision algorithm for `rays` rays of `kind` on `triangles` (flattened from `scene`; path
/// sample rays need the scene's camera, lights and normals). Throws vf::Error on bad options or an
/// empty triangle set. Cost: one grid build plus tracing the S sample rays once.
Selection select_structure(const Scene& scene, const TriangleSet& triangles, std::uint64_t rays,
                           const Calibration& calibration, RayKind kind, const SelectOptions& options = {});

}  // namespace vf
