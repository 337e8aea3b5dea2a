#pragma once
/// \file The paper's evaluation (section 4) as arithmetic on stored measurements: exact against
/// estimated R_C with leave-one-out calibration, the leave-k-out experiment over random splits, and how
/// often the decision picks the structure that really finishes first. An estimate only uses what the
/// algorithm may know: of the estimated scene its N and its sampled grid time; of the calibration scenes
/// everything.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
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

/// The planner on one held-out scene for one workload.
struct PlanOutcome {
  std::string scene;             ///< The scene's name.
  std::string chosen;            ///< What the planner picked with the model fitted on the other scenes.
  std::string best;              ///< The measured fastest among the candidates allowed (measured error <= E).
  double chosen_ms = 0.0;        ///< Measured total of the choice (build + R rays + U updates; + the build of a field measured in vain).
  double best_ms = 0.0;          ///< Measured total of the best.
  bool error_kept = true;        ///< The choice's measured error is within E.
  int measured = 0;              ///< Fields the plan measured to settle (Plan::to_measure, until none is left).
  int measured_kept = 0;         ///< Of those, the ones that met E (each became the choice); the others' builds count in chosen_ms.

  /// The choice is the best (or as fast, to a part in 1e9) and keeps the error.
  bool right() const { return error_kept && chosen_ms <= best_ms * (1.0 + 1e-9); }
  /// chosen_ms / best_ms.
  double regret() const { return best_ms > 0.0 ? chosen_ms / best_ms : 1.0; }
};

/// For each scene with plan measurements (at least two are needed; throws vf::Error): the planner's
/// choice for `request` (no memory limit) with the model fitted on every other scene, against the
/// measured totals of that scene's candidates. Candidates a scene did not measure are not chosen.
std::vector<PlanOutcome> plan_leave_one_out(std::span<const SceneMeasurement> scenes, const PlanRequest& request, int threads);

/// A field sized from a target error on one held-out scene.
struct TargetRmsOutcome {
  std::string scene;
  double target = 0.0;            ///< E.
  std::string chosen;             ///< The field the error model (fitted on the other scenes) picks; empty: none predicted to meet E.
  double chosen_rms = 0.0;        ///< Its measured RMS.
  double chosen_bytes = 0.0;      ///< Its measured memory.
  double smallest_bytes = 0.0;    ///< The smallest measured field that meets E; 0 when none does.
  int measured = 0;               ///< Fields measured on the way (those the fit cannot rule out and the bound does not admit).

  /// The choice meets E (a refusal is right when no measured field meets E).
  bool met() const { return chosen.empty() ? smallest_bytes == 0.0 : chosen_rms <= target; }
  /// chosen_bytes / smallest_bytes (0 when either is missing).
  double size_ratio() const { return chosen.empty() || smallest_bytes == 0.0 ? 0.0 : chosen_bytes / smallest_bytes; }
};

/// field_for_target_rms with the error model fitted on every other scene, measuring with the scene's
/// measured RMS, for each scene with field measurements, against that scene's measured fields. Needs two such scenes (throws vf::Error).
std::vector<TargetRmsOutcome> target_rms_leave_one_out(std::span<const SceneMeasurement> scenes, double target, int threads);

}  // namespace vf
