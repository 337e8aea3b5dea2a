#pragma once
/// \file The per-machine calibration of the grids-vs-hierarchies selection (Hapala, Karlik, Havran,
/// section 3): raw measurements of a set of scenes (uniform grid and SAH kd-tree build times, per-ray
/// times for random and path-tracing rays) and the constants derived from them (eqs. 7 and 8), stored
/// as versioned JSON.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "visfield/accel/grid_stats.hpp"
#include "visfield/render/ray_kind.hpp"
#include "visfield/select/plan.hpp"

namespace vf {

/// The ray kinds a calibration measures (the paper's two workloads), in file and report order.
inline constexpr std::array<RayKind, 2> kCalibratedKinds{RayKind::random, RayKind::path};

/// Index of `kind` in kCalibratedKinds (0 for random, 1 for path); throws vf::Error for a kind the
/// calibration does not measure.
std::size_t calibrated_kind_index(RayKind kind);

/// Per-ray times of one scene for one ray kind, in microseconds per ray on the calibration's threads:
/// single-thread time divided by the thread count (see median_batch_query_us).
struct RayTimings {
  std::uint64_t ray_count = 0;         ///< M: rays traced through both structures.
  double grid_us = 0.0;                ///< t_R^G: grid, on the M rays (large_set_query_us).
  double tree_us = 0.0;                ///< t_R^H: kd-tree, the same rays.
  std::uint64_t sample_count = 0;      ///< S: the sample rays the decision algorithm traces.
  double grid_sample_us = 0.0;         ///< t_R^G estimated from the S sample rays only (sample_query_us: what the algorithm knows).

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const RayTimings&) const = default;
};

/// Everything measured on one scene. Build times in milliseconds.
struct SceneMeasurement {
  std::string name;                       ///< The scene as the user named it.
  std::uint64_t triangles = 0;            ///< N, triangles after flattening (>= 1).
  std::array<int, 3> grid_resolution{};   ///< Grid cells per axis.
  std::uint64_t grid_memory_bytes = 0;    ///< Bytes held by the grid.
  GridStatistics grid_statistics;         ///< The paper's statistics of the grid's cells.
  double grid_build_ms = 0.0;             ///< T_B^G.
  double tree_build_ms = 0.0;             ///< T_B^H.
  std::uint64_t tree_memory_bytes = 0;    ///< Bytes held by the kd-tree.
  std::array<RayTimings, 2> rays{};       ///< Indexed by calibrated_kind_index().
  PlanMeasurement plan;                   ///< Every candidate of the planner on this scene (empty when not measured).

  /// Timings of `kind`.
  const RayTimings& timings(RayKind kind) const { return rays[calibrated_kind_index(kind)]; }

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const SceneMeasurement&) const = default;
};

/// The per-machine constants of eqs. 7 and 8.
struct CalibrationConstants {
  double build_ms_per_n_log2_n = 0.0;               ///< C_B: T_B^H ~ C_B * N log2 N, milliseconds.
  std::array<double, 2> ray_us_per_log2_n{};         ///< C_R per ray kind: t_R^H ~ C_R * log2 N, microseconds.

  /// C_R of `kind`.
  double ray_us(RayKind kind) const { return ray_us_per_log2_n[calibrated_kind_index(kind)]; }

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const CalibrationConstants&) const = default;
};

/// Where a calibration was measured.
struct MachineInfo {
  std::string hostname;
  int threads = 0;        ///< TBB threads in force while measuring.
  std::string cpu_model;  ///< "model name" of /proc/cpuinfo ("unknown" where absent).

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const MachineInfo&) const = default;
};

/// How the measurements are taken; stored in the calibration file so a report can say what it reproduces.
struct CalibrationOptions {
  std::uint64_t rays = 20000;        ///< M, rays of each kind per scene, each traced once per structure.
  std::uint64_t sample_rays = 500;   ///< S, sample rays of the decision algorithm (100..1000 in the paper).
  int build_repetitions = 3;         ///< Builds per structure; the median counts.
  int path_bounces = 2;              ///< Diffuse bounces of the path-tracing rays.
  std::uint64_t seed = 1;            ///< Seed of every ray set.

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const CalibrationOptions&) const = default;
};

/// A calibration: machine, settings, per-scene measurements and the constants derived from them.
struct Calibration {
  MachineInfo machine;
  CalibrationOptions settings;
  CalibrationConstants constants;
  PlanModel plan;                        ///< The planner's constants and field error model (fitted on the scenes' plan measurements).
  std::vector<SceneMeasurement> scenes;  ///< Empty for the built-in calibration (constants only).

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const Calibration&) const = default;
};

/// log2 N as the cost model uses it: log2(max(N, 2)), so a one-triangle scene costs like two and no
/// cost is ever zero.
double cost_log2(std::uint64_t triangles);

/// The constants of eqs. 7 and 8 over `scenes[i]` for each i in `subset`:
/// C_B = (1/s) sum T_B^H(i) / (N(i) log2 N(i)), C_R(kind) = (1/s) sum t_R^H(i) / log2 N(i).
/// Throws vf::Error when `subset` is empty or names a scene out of range.
CalibrationConstants compute_constants(std::span<const SceneMeasurement> scenes, std::span<const std::size_t> subset);

/// The constants over every scene of `scenes`. Throws vf::Error when `scenes` is empty.
CalibrationConstants compute_constants(std::span<const SceneMeasurement> scenes);

/// The calibration as JSON text: {"format": "visfield-calibration", "version": 2, "machine", "settings",
/// "constants", "plan", "scenes"}.
std::string calibration_to_json(const Calibration& calibration);

/// Parses calibration JSON, validating every field; `source` names the file in messages. When scenes
/// hold plan measurements, the planner's model is fitted anew from them (fit_plan_model), so a file
/// written by an older fit gets this build's. Throws a
/// one-line vf::Error naming `source` and the field on malformed JSON, a wrong "format" or "version",
/// a missing field or ray kind, a wrong type or an out-of-range value.
Calibration calibration_from_json(const std::string& text, const std::string& source);

/// Writes `calibration` to `path` atomically (temporary file, then rename). Throws vf::Error on I/O failure.
void save_calibration(const std::filesystem::path& path, const Calibration& calibration);

/// Reads and validates a calibration file (see calibration_from_json). Throws vf::Error naming the file.
Calibration load_calibration(const std::filesystem::path& path);

/// Refuses (vf::Error naming `source`) a calibration measured on another CPU model or with another
/// thread count than `here`: its timings would mislead the selection. The built-in calibration is
/// not checked by its callers (it is the documented approximation for machines without their own).
void require_calibration_for(const Calibration& calibration, const MachineInfo& here, const std::string& source);

/// The constants measured on the project's build machine (see builtin_calibration.cpp for the command
/// and the figures); used when no calibration file is given. No scenes.
const Calibration& builtin_calibration();

/// The machine this process runs on, with `threads` TBB threads in force.
MachineInfo this_machine(int threads);

}  // namespace vf
