#include "visfield/select/calibrate.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "visfield/accel/grid_stats.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/select/timing.hpp"

namespace vf {
namespace {

template <class Integer>
void check_range(const char* name, Integer value, Integer lo, Integer hi) {
  if (value < lo || value > hi)
    throw Error(std::string("calibration: ") + name + " must be in " + std::to_string(lo) + ".." + std::to_string(hi) +
                ", got " + std::to_string(value));
}

}  // namespace

NamedScene load_named_scene(const std::string& spec) {
  NamedScene named;
  named.name = spec;
  named.scene = load_scene(spec);
  named.triangles = flatten(named.scene);
  if (named.triangles.size() == 0) throw Error(spec + ": the scene has no non-degenerate triangles");
  return named;
}

void validate_calibration_options(const CalibrationOptions& options) {
  check_range<std::uint64_t>("rays", options.rays, 1, 1'000'000'000);
  check_range<std::uint64_t>("sample_rays", options.sample_rays, 5, 1'000'000);
  check_range("build_repetitions", options.build_repetitions, 1, 1000);
  check_range("path_bounces", options.path_bounces, 0, 16);
}

SceneMeasurement measure_scene(const NamedScene& named, const CalibrationOptions& options) {
  validate_calibration_options(options);
  const TriangleSet& triangles = named.triangles;
  if (triangles.size() == 0) throw Error(named.name + ": the scene has no non-degenerate triangles");

  const int threads = threads_in_force();
  SceneMeasurement m;
  m.name = named.name;
  m.triangles = triangles.size();
  auto grid = timed_build([&] { return UniformGrid::build(triangles); }, options.build_repetitions);
  m.grid_build_ms = grid.build_ms;
  m.grid_resolution = grid.structure.resolution();
  m.grid_memory_bytes = grid.structure.stats().memory_bytes;
  m.grid_statistics = compute_grid_statistics(grid.structure);
  // The decision algorithm's sample, right after the grid build as the planner's profile takes it (the
  // build leaves the grid in cache, and so would an application's).
  for (RayKind kind : kCalibratedKinds) {
    const SampleTiming sample = time_sample(kind, grid.structure, named.scene, triangles.bounds, options.sample_rays,
                                            options.seed + 1, options.path_bounces, threads);
    m.rays[calibrated_kind_index(kind)].sample_count = sample.count;
    m.rays[calibrated_kind_index(kind)].grid_sample_us = sample.query_us;
  }
  auto tree = timed_build([&] { return KdTree::build(triangles); }, options.build_repetitions);
  m.tree_build_ms = tree.build_ms;
  m.tree_memory_bytes = tree.structure.stats().memory_bytes;

  for (RayKind kind : kCalibratedKinds) {
    RayTimings& t = m.rays[calibrated_kind_index(kind)];
    // The kd-tree generates the path rays (it is the faster tracer); any exact structure gives the same rays.
    const QuerySet queries = make_queries(kind, tree.structure, named.scene, triangles.bounds, options.rays, options.seed,
                                          options.path_bounces);
    t.ray_count = queries.size();
    t.grid_us = large_set_query_us(grid.structure, queries, threads);
    t.tree_us = large_set_query_us(tree.structure, queries, threads);
  }
  return m;
}

PlanModel fit_plan_model(std::span<const SceneMeasurement> scenes, int threads) {
  std::vector<PlanMeasurement> plans;
  std::vector<std::size_t> measured;
  for (const SceneMeasurement& s : scenes) {
    if (!s.plan.candidates.empty()) measured.push_back(plans.size());
    plans.push_back(s.plan);
  }
  if (measured.empty()) {
    PlanModel none;
    none.threads = std::max(threads, 1);
    none.constants.resize(plan_candidates().size());
    return none;
  }
  return fit_plan_model(plans, measured, threads);
}

Calibration calibrate(const std::vector<NamedScene>& scenes, const CalibrationOptions& options,
                      const std::function<void(const SceneMeasurement&)>& on_scene,
                      const std::function<PlanMeasurement(const NamedScene&)>& measure_plan) {
  validate_calibration_options(options);
  if (scenes.empty()) throw Error("calibration: no scenes given");
  Calibration c;
  c.machine = this_machine(threads_in_force());
  c.settings = options;
  for (const NamedScene& scene : scenes) {
    c.scenes.push_back(measure_scene(scene, options));
    if (measure_plan) c.scenes.back().plan = measure_plan(scene);
    if (on_scene) on_scene(c.scenes.back());
  }
  c.constants = compute_constants(c.scenes);
  c.plan = fit_plan_model(c.scenes, c.machine.threads);
  return c;
}

}  // namespace vf
