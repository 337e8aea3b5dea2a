#pragma once
/// \file The paper's evaluation (section 4) as arithmetic on stored measurements: exact against
/// estimated R_C with leave-one-out calibration, the leave-k-out experiment over random splits, and how
/// often the decision picks the structure that really finishes first. An estimate only uses what the
/// algorithm may know: of the estimated scene its N and its sampled grid time; of the calibration scenes
/// everything.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visfield/select/calibration.hpp"
#include "visfield/select/critical_rays.hpp"

namespace vf {

/// The constants of eqs. 7 and 8 over every scene but scenes[left_out] (throws vf::Error when none is left).
CalibrationConstants constants_without(std::span<const SceneMeasurement> scenes, std::size_t left_out);

/// Exact and estimated R_C of one scene.
struct CriticalRaysEstimate {
  double exact = 0.0;          ///< From both structures' measurements (may be +infinity).
  double estimate = 0.0;       ///< Decision algorithm's estimate (may be +infinity).
  double error_percent = 0.0;  ///< 100 (estimate - exact) / exact; NaN when undefined.
};

/// For each scene, its exact R_C and the estimate calibrated on all the other scenes. Needs at least two
/// scenes (throws vf::Error otherwise).
std::vector<CriticalRaysEstimate> leave_one_out(std::span<const SceneMeasurement> scenes, RayKind kind,
                                                double epsilon = kCriticalEpsilon);

/// One row of the leave-k-out experiment: calibrate on k random scenes, estimate the others.
struct LeaveKOutRow {
  std::size_t k = 0;                   ///< Calibration scenes per split.
  std::size_t splits = 0;              ///< Random splits.
  std::size_t estimates = 0;           ///< (split, scene) pairs with a defined error.
  std::size_t undefined = 0;           ///< Pairs left out: exact or estimated R_C infinite, or exact R_C 0.
  double mean_error_percent = 0.0;     ///< Mean of the signed errors (NaN when estimates == 0).
  double mean_abs_error_percent = 0.0; ///< Mean of the absolute errors (NaN when estimates == 0).
};

/// Rows k = 1 .. scenes - 1; split j of row k calibrates on the first k scenes of a Fisher-Yates
/// shuffle drawn from Rng(seed, k, j). Needs at least two scenes and splits >= 1 (throws vf::Error).
std::vector<LeaveKOutRow> leave_k_out(std::span<const SceneMeasurement> scenes, RayKind kind, std::size_t splits,
                                      std::uint64_t seed, double epsilon = kCriticalEpsilon);

/// Measured total time of R rays with the grid: T_B^G + R t_R^G, milliseconds.
double grid_total_ms(const SceneMeasurement& scene, RayKind kind, double rays);
/// Measured total time of R rays with the kd-tree: T_B^H + R t_R^H, milliseconds.
double tree_total_ms(const SceneMeasurement& scene, RayKind kind, double rays);

/// How well the decision does for one workload size.
struct DecisionRow {
  double rays = 0.0;              ///< R.
  std::size_t scenes = 0;         ///< Scenes decided.
  std::size_t right = 0;          ///< The decision (leave-one-out calibration) picked the faster total, T_B + R t_R.
  std::size_t grid_right = 0;     ///< "Always the grid" would have been right.
  std::size_t tree_right = 0;     ///< "Always the kd-tree" would have been right.
  double mean_time_ratio = 0.0;   ///< Mean over scenes of the decision's time / the faster total. The decision
                                  ///< always pays T_B^G, then R t_R^G, or T_B^H + R t_R^H after a kd-tree pick.
};

/// One row per entry of `ray_counts` (ties between the totals count as right for both). Needs at least
/// two scenes (throws vf::Error).
std::vector<DecisionRow> decision_accuracy(std::span<const SceneMeasurement> scenes, RayKind kind,
                                           std::span<const double> ray_counts, double epsilon = kCriticalEpsilon);

}  // namespace vf
