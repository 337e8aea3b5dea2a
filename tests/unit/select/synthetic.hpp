#pragma once
// Synthetic scene measurements with known answers, for the arithmetic of calibration and estimation.

#include <cmath>
#include <string>
#include <vector>

#include "visfield/select/calibration.hpp"

namespace vf::test {

// A measurement that follows the cost model exactly: T_B^H = cb N log2 N, t_R^H = cr log2 N (both kinds),
// with the given grid numbers (sample time = full time).
inline SceneMeasurement model_scene(const std::string& name, std::uint64_t n, double cb, double cr_random, double cr_path,
                                    double grid_build_ms, double grid_random_us, double grid_path_us) {
  SceneMeasurement m;
  m.name = name;
  m.triangles = n;
  m.grid_resolution = {4, 5, 6};
  m.grid_memory_bytes = 1000 + n;
  m.grid_statistics.cell_count = 120;
  m.grid_statistics.empty_cells = 30;
  m.grid_statistics.sparseness = 0.25;
  m.grid_statistics.max_refs = 17;
  m.grid_statistics.mean = 2.5;
  m.grid_statistics.variance = 6.25;
  m.grid_statistics.std_dev = 2.5;
  m.grid_statistics.skewness = -0.5;
  m.grid_statistics.kurtosis = 1.75;
  m.grid_build_ms = grid_build_ms;
  const double log_n = std::log2(static_cast<double>(n));
  m.tree_build_ms = cb * static_cast<double>(n) * log_n;
  m.tree_memory_bytes = 2000 + n;
  m.rays[calibrated_kind_index(RayKind::random)] = {10000, grid_random_us, cr_random * log_n, 500, grid_random_us};
  m.rays[calibrated_kind_index(RayKind::path)] = {10000, grid_path_us, cr_path * log_n, 500, grid_path_us};
  return m;
}

// The constants every synthetic plan measurement follows: candidate i builds in (i + 1) ms per unit of
// its build feature, traces kind k in 0.01 (i + 1) (k + 1) us per unit of its ray feature, updates in
// 0.5 ms per unit; fields follow the error model `error`.
inline PlanModel synthetic_plan_model(int threads = 2) {
  PlanModel model;
  model.threads = threads;
  for (std::size_t i = 0; i < plan_candidates().size(); ++i) {
    CandidateConstants c;
    c.build_ms = static_cast<double>(i + 1);
    for (std::size_t k = 0; k < kPlanKinds; ++k) c.ray_us[k] = 0.01 * static_cast<double>((i + 1) * (k + 1));
    c.update_ms = plan_candidates()[i].updatable ? 0.5 : 0.0;
    if (plan_candidates()[i].shape == CostShape::brute) c.ray_exponent.fill(1.25);  // caches give out as N grows
    model.constants.push_back(c);
  }
  model.field_error.coefficients = {0.125, -0.5, 0.0625, -0.25, 0.03125};
  model.field_error.samples = 9;
  return model;
}

// A profile of a scene of `n` triangles in `objects` copies of one mesh, whose field probe measured
// an RMS of 2.
inline SceneProfile synthetic_profile(std::uint64_t n, std::uint64_t objects, double ao_occluded, int threads = 2) {
  SceneProfile p;
  p.triangles = n * objects;
  p.unique_triangles = n;
  p.objects = objects;
  p.mesh_log2_sum = std::log2(static_cast<double>(n));
  p.grid_build_ms = 1e-3 * static_cast<double>(p.triangles);
  for (std::size_t k = 0; k < kPlanKinds; ++k) p.grid_sample_us[k] = 0.05 * static_cast<double>(k + 1);
  p.bvh_build_ms = 1e-4 * static_cast<double>(n);
  for (std::size_t k = 0; k < kPlanKinds; ++k) p.bvh_sample_us[k] = 0.02 * static_cast<double>(k + 1);
  p.ao_occluded = ao_occluded;
  p.field_probe_rms = 2.0;
  p.threads = threads;
  return p;
}

// What measure_plan would record on a scene with `profile` if every candidate followed `model` exactly
// (fields' RMS = the model's prediction; memory = 1000 (i + 1) bytes).
inline PlanMeasurement synthetic_plan_measurement(const PlanModel& model, const SceneProfile& profile) {
  PlanMeasurement m;
  m.profile = profile;
  for (std::size_t i = 0; i < plan_candidates().size(); ++i) {
    const PlanCandidate& c = plan_candidates()[i];
    CandidateMeasurement cm;
    cm.spec = std::string(c.spec);
    cm.build_ms = model.constants[i].build_ms * build_feature(c, profile);
    cm.memory_bytes = 1000 * (i + 1);
    for (std::size_t k = 0; k < kPlanKinds; ++k)
      cm.ray_us[k] = c.answers(kRayKinds[k])
                         ? model.constants[i].ray_us[k] * std::pow(ray_feature(c, profile, kRayKinds[k]), model.constants[i].ray_exponent[k])
                         : -1.0;
    cm.update_ms = c.updatable ? model.constants[i].update_ms * update_feature(c, profile) : -1.0;
    cm.ao_rms = c.approximate() ? model.field_error.predict(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms) : 0.0;
    m.candidates.push_back(cm);
  }
  return m;
}

}  // namespace vf::test
