#pragma once
/// \file The calibration phase: measure the uniform grid and the SAH kd-tree on a set of scenes.

#include <functional>
#include <vector>

#include "visfield/select/calibration.hpp"
#include "visfield/select/workload.hpp"

namespace vf {

/// Throws vf::Error naming the bad setting unless 1 <= rays <= 1e9, 5 <= sample_rays <= 1e6,
/// build_repetitions in 1..1000 and path_bounces in 0..16.
void validate_calibration_options(const CalibrationOptions& options);

/// Measures one scene with the default UniformGrid and KdTree configs: each built
/// options.build_repetitions times (median T_B^G, T_B^H); per ray kind, options.rays queries (seed
/// options.seed) through both, and options.sample_rays queries drawn with seed options.seed + 1 through
/// the grid alone (the decision algorithm's sample, timed by sample_query_us); per-ray times of the
/// M queries by large_set_query_us.
/// Timings use TBB's threads in force. Throws vf::Error on bad options. Cost: dominated by the
/// kd-tree builds, O(build_repetitions * N log N).
SceneMeasurement measure_scene(const NamedScene& scene, const CalibrationOptions& options);

/// The calibration phase over `scenes` (at least one): measure_scene on each, in order, with its plan
/// measurement from `measure_plan` when given (the registry's measure_plan: every structure), calling
/// `on_scene` after each (for progress); then the constants of eqs. 7 and 8 and the planner's model over
/// all of them.
Calibration calibrate(const std::vector<NamedScene>& scenes, const CalibrationOptions& options,
                      const std::function<void(const SceneMeasurement&)>& on_scene = {},
                      const std::function<PlanMeasurement(const NamedScene&)>& measure_plan = {});

/// The planner's model over every scene of `scenes` that holds a plan measurement, for `threads`.
PlanModel fit_plan_model(std::span<const SceneMeasurement> scenes, int threads);

}  // namespace vf
