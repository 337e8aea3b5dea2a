#include "select_cli_support.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_support.hpp"
#include "visfield/core/error.hpp"
#include "visfield/registry/planning.hpp"
#include "visfield/select/calibrate.hpp"

namespace vf::cli {

NamedScene load_named(const std::string& spec) {
  NamedScene named = load_named_scene(spec);
  warn_degenerate_triangles(spec, named.triangles.degenerate_count);
  return named;
}

std::uint64_t ray_count(double value, const std::string& option) {
  if (!(value >= 0.0) || value > 1e15 || std::floor(value) != value)
    throw Error(option + ": expected a whole number of rays in 0..1e15, got " + std::to_string(value));
  return static_cast<std::uint64_t>(value);
}

std::string measurement_line(const SceneMeasurement& m) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer,
                "%s: N %llu, sigma %.2f, build grid %.2f ms, kdtree %.2f ms; random t^G %.3f us t^H %.3f us; path "
                "t^G %.3f us t^H %.3f us",
                m.name.c_str(), static_cast<unsigned long long>(m.triangles), m.grid_statistics.std_dev, m.grid_build_ms,
                m.tree_build_ms, m.timings(RayKind::random).grid_us, m.timings(RayKind::random).tree_us,
                m.timings(RayKind::path).grid_us, m.timings(RayKind::path).tree_us);
  return buffer;
}

CalibrationOptions MeasureFlags::options() const {
  CalibrationOptions o;
  o.rays = ray_count(rays, "--rays");
  o.sample_rays = ray_count(sample_rays, "--sample-rays");
  o.build_repetitions = build_repetitions;
  o.path_bounces = bounces;
  o.seed = seed;
  validate_calibration_options(o);
  return o;
}

void add_measure_flags(CLI::App& cmd, MeasureFlags& flags) {
  cmd.add_option("--rays", flags.rays, "M: rays of each kind timed per scene through both structures")
      ->check(number_in(1.0, 1e9))
      ->capture_default_str();
  cmd.add_option("--sample-rays", flags.sample_rays, "S: sample rays the decision algorithm times through the grid")
      ->check(number_in(5.0, 1e6))
      ->capture_default_str();
  cmd.add_option("--build-repetitions", flags.build_repetitions, "Builds per structure (the median counts)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd.add_option("--bounces", flags.bounces, "Diffuse bounces of the path-tracing rays")->check(CLI::Range(0, 16))->capture_default_str();
  cmd.add_option("--seed", flags.seed, "Seed of the ray sets")->capture_default_str();
  cmd.add_flag("--no-plan", flags.no_plan,
               "Measure the grid and the kd-tree only (Hapala et al.), not every structure for the planner (`auto`, `select`)");
}

Calibration calibrate_with_progress(const std::vector<NamedScene>& scenes, const MeasureFlags& flags) {
  const CalibrationOptions options = flags.options();
  std::function<PlanMeasurement(const NamedScene&)> measure;
  if (!flags.no_plan)
    measure = [&](const NamedScene& scene) {
      return measure_plan(scene, options, [&](std::string_view spec) { std::cerr << "  " << scene.name << ": " << spec << "\n"; });
    };
  return calibrate(
      scenes, options,
      [](const SceneMeasurement& m) {
        std::cout << "measured " << measurement_line(m);
        if (!m.plan.candidates.empty()) std::cout << "; " << m.plan.candidates.size() << " structures for the planner";
        std::cout << std::endl;
      },
      measure);
}

}  // namespace vf::cli
