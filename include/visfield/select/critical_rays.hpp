#pragma once
/// \file The critical ray count R_C of the grids-vs-hierarchies paper: below it the uniform grid
/// finishes first, above it building the kd-tree pays off.

#include <cstdint>

#include "visfield/select/calibration.hpp"

namespace vf {

/// The paper's epsilon in R_C = T_B^H / (t_R^G (1 + eps) - t_R^H): keeps the denominator off zero.
inline constexpr double kCriticalEpsilon = 0.01;

/// Estimated R_C (decision algorithm, step 6) from the hierarchy's estimated build time (ms) and the
/// per-ray times (microseconds): tree_build_ms / (grid_ray_us (1 + epsilon) - tree_ray_us), in rays.
/// +infinity when tree_ray_us >= grid_ray_us (step 5: the grid is never slower per ray) or the
/// denominator is not positive.
double estimated_critical_rays(double tree_build_ms, double grid_ray_us, double tree_ray_us,
                               double epsilon = kCriticalEpsilon);

/// Exact R_C from measuring both structures (the paper's Table 1): the ray count R at which
/// T_B^G + R t_R^G = T_B^H + R t_R^H, i.e. (T_B^H - T_B^G) / (t_R^G - t_R^H). +infinity when
/// t_R^G <= t_R^H (the grid never loses); 0 when the kd-tree is no slower to build and faster per ray.
double exact_critical_rays(double grid_build_ms, double tree_build_ms, double grid_ray_us, double tree_ray_us);

/// exact_critical_rays of `scene`'s measurements for `kind` (full M-ray timings of both structures).
double exact_critical_rays(const SceneMeasurement& scene, RayKind kind);

/// Estimated T_B^H = C_B N log2 N (eq. 7), milliseconds.
double estimated_tree_build_ms(const CalibrationConstants& constants, std::uint64_t triangles);

/// Estimated t_R^H = C_R log2 N (eq. 8), microseconds per ray.
double estimated_tree_ray_us(const CalibrationConstants& constants, RayKind kind, std::uint64_t triangles);

/// The R_C the decision algorithm estimates for a scene of `triangles` triangles whose grid traced the
/// sample rays in `grid_sample_us` per ray, with `constants` from the calibration scenes.
double estimated_critical_rays(const CalibrationConstants& constants, RayKind kind, std::uint64_t triangles,
                               double grid_sample_us, double epsilon = kCriticalEpsilon);

/// Step 7 of the decision algorithm: true (keep the grid) when rays < critical_rays.
bool grid_wins(double rays, double critical_rays);

/// Relative error of an estimate in percent, 100 (estimate - exact) / exact; NaN when either value is
/// infinite or exact is 0 (the paper's error is undefined there).
double estimate_error_percent(double estimate, double exact);

}  // namespace vf
