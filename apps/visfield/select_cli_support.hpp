#pragma once
/// \file Pieces shared by the selection subcommands (calibrate, select, stats, report).

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "visfield/select/calibration.hpp"
#include "visfield/select/workload.hpp"

namespace vf::cli {

/// Loads and flattens `spec` (load_named_scene), warning on stderr about zero-area triangles left out.
NamedScene load_named(const std::string& spec);

/// `value` (from an option parsed as a number so "1e6" works) as a ray count; throws vf::Error naming
/// `option` unless it is a whole number in 0..1e15.
std::uint64_t ray_count(double value, const std::string& option);

/// One line per measured scene, for progress output: N, builds and per-ray times of both kinds.
std::string measurement_line(const SceneMeasurement& m);

/// Calibration options from the flags the calibrate and report commands share.
struct MeasureFlags {
  double rays = 20000;
  double sample_rays = 500;
  int build_repetitions = 3;
  int bounces = 2;
  std::uint64_t seed = 1;
  bool no_plan = false;  ///< Measure the grid and the kd-tree only, not every structure for the planner.

  /// The validated options.
  CalibrationOptions options() const;
};

/// Registers --rays, --sample-rays, --build-repetitions, --bounces, --seed and --no-plan on `cmd`.
void add_measure_flags(CLI::App& cmd, MeasureFlags& flags);

/// calibrate() over `scenes` with `flags`, every planner candidate measured too (measure_plan) unless
/// --no-plan; prints a line per scene measured.
Calibration calibrate_with_progress(const std::vector<NamedScene>& scenes, const MeasureFlags& flags);

}  // namespace vf::cli
