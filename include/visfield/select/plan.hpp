#pragma once
/// \file The planner: one choice across every structure. For a scene's profile (statistics known
/// before any costly build) and a workload (R rays of one kind, U object updates, an error tolerance
/// E, the memory limit), it predicts each candidate's build, ray and update time, memory and error
/// from calibrated constants, and picks the fastest candidate that fits. The cost model: each
/// candidate's time is a constant per unit of a feature of the scene (N log2 N for a tree's build,
/// the grid's and the BVH's own sampled time per ray, ...); the constants are geometric means of
/// measured / feature over the calibration scenes. Fields add an error model: log RMS linear in
/// log positions, log directions and log of the scene's sampled AO occlusion.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/render/ray_kind.hpp"

namespace vf {

/// Which feature of the scene a candidate's costs grow with.
enum class CostShape {
  grid,       ///< build ~ the profile's own grid build; per ray ~ a power of the grid's time on the profile's sample rays
  tree,       ///< build ~ N log2 N; per ray ~ the profile's BVH sample x log2 N / (log2 U + log2 O) (its depth over the sampled tree's)
  two_level,  ///< build ~ U log2 U + O log2 O (U unique triangles, O objects); per ray ~ the profile's BVH sample; update ~ O log2 O
  beam,       ///< build ~ N log2 N; per ray ~ log2 N; update ~ N / O (one object's triangles)
  brute,      ///< build ~ N; per ray ~ a power of N
  field,      ///< build ~ positions directions^2 (sum of log2 triangles of the meshes); per ray ~ 1 + log2 O
};

/// One structure with one choice of its parameters, as the planner weighs it.
struct PlanCandidate {
  std::string_view spec;  ///< The registry spec that builds it.
  CostShape shape;
  bool updatable;         ///< Moves objects in place; otherwise an update rebuilds it.
  int positions = 0;      ///< Field tables: positional samples (field shape only).
  int directions = 0;     ///< Field tables: N of the N x N direction tables (field shape only).

  /// Approximate (a field): its error must be within the request's tolerance.
  bool approximate() const { return shape == CostShape::field; }
  /// Whether it answers `kind`'s rays: fields answer occlusion (AO and shadow rays) only.
  bool answers(RayKind kind) const { return !approximate() || is_occlusion_kind(kind); }
};

/// The smallest field candidate, built on a scene to probe how well fields fit it (its RMS is the
/// error model's per-scene statistic).
inline constexpr std::string_view kFieldProbe = "field:positions=1090,directions=16";

/// Sample rays of each kind the planner's profile traces through its grid.
inline constexpr std::size_t kProfileSampleRays = 2000;

/// Every candidate, in table order (the order of PlanModel::constants).
std::span<const PlanCandidate> plan_candidates();

/// Index of the candidate whose spec is `spec` in plan_candidates(), or npos.
std::size_t plan_candidate_index(std::string_view spec);

/// Number of ray kinds the planner tells apart (kRayKinds, in that order).
inline constexpr std::size_t kPlanKinds = kRayKinds.size();

/// Index of `kind` in kRayKinds.
std::size_t plan_kind_index(RayKind kind);

/// What the planner knows of a scene: counts, and sample rays through a uniform grid (Hapala et al.'s
/// step: cheap to build, and its time per ray tells how hard the scene is for a grid) and the same rays
/// through a two-level BVH (each mesh once: cheap for many copies, and its time per ray tells how hard
/// the scene and the ray kind are for every tree).
struct SceneProfile {
  std::uint64_t triangles = 0;         ///< N, triangles over every object (as flattened).
  std::uint64_t unique_triangles = 0;  ///< U, triangles of the meshes objects use, each mesh once.
  std::uint64_t objects = 0;           ///< O, objects (instances).
  double mesh_log2_sum = 0.0;          ///< Sum over the meshes objects use of log2 max(triangles, 2).
  double grid_build_ms = 0.0;          ///< The profile's grid build; 0 = no grid (the scene was too large to flatten).
  std::array<double, kPlanKinds> grid_sample_us{};  ///< Per kind: the grid's microseconds per sample ray; 0 = not sampled.
  double bvh_build_ms = 0.0;           ///< The profile's two-level BVH build (each mesh once, then the objects).
  std::array<double, kPlanKinds> bvh_sample_us{};   ///< Per kind: the two-level BVH's microseconds per sample ray (the same rays); 0 = not sampled.
  double ao_occluded = 0.0;            ///< Fraction of the sampled AO rays that are occluded (how enclosed the scene is).
  double field_probe_rms = -1.0;       ///< RMS (0-255) of the AO image through kFieldProbe against the exact one; < 0 = not probed.
  int threads = 1;                     ///< Threads the sample times are for.

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const SceneProfile&) const = default;
};

/// Scenes with more triangles than this are not flattened for a profile: their grid is not sampled
/// (the flattening alone would cost more than most structures' builds).
inline constexpr std::uint64_t kProfileFlattenLimit = 16'000'000;

/// The profile of `scene`: counts; a two-level BVH and `sample_rays` rays of each of `kinds` (and of ao,
/// for the occluded fraction) drawn through it with `seed` (path rays with `path_bounces` bounces) and
/// timed through it as the calibration times its candidates (batch_passes_query_us, with 9 timed
/// passes); with `triangles` (its flattening; nullptr for a scene too large to flatten), a uniform grid
/// built over them and the same rays timed through it. Cost: the two builds plus the samples.
SceneProfile profile_scene(const Scene& scene, const TriangleSet* triangles, std::span<const RayKind> kinds,
                           std::size_t sample_rays, std::uint64_t seed, int path_bounces);

/// Feature a candidate's build time is proportional to, for `profile`.
double build_feature(const PlanCandidate& candidate, const SceneProfile& profile);
/// Feature a candidate's time per ray of `kind` is proportional to; 0 when it cannot be predicted
/// (the grid without a sample of that kind).
double ray_feature(const PlanCandidate& candidate, const SceneProfile& profile, RayKind kind);
/// Feature the time of one in-place object update is proportional to (updatable candidates).
double update_feature(const PlanCandidate& candidate, const SceneProfile& profile);

/// A candidate's constants: milliseconds or microseconds per unit of its features; 0 = never measured.
struct CandidateConstants {
  double build_ms = 0.0;                     ///< Build, ms per build_feature.
  std::array<double, kPlanKinds> ray_us{};   ///< Per kind, microseconds per ray per ray_feature^exponent.
  std::array<double, kPlanKinds> ray_exponent{1.0, 1.0, 1.0, 1.0, 1.0};  ///< Per kind, the power of ray_feature (1 but for the grid and brute force).
  double update_ms = 0.0;                    ///< One in-place update, ms per update_feature.

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const CandidateConstants&) const = default;
};

/// Positional samples of kFieldProbe.
inline constexpr int kFieldProbePositions = 1090;
/// N of kFieldProbe's N x N direction tables.
inline constexpr int kFieldProbeDirections = 16;
/// Features of the fields' error model.
inline constexpr std::size_t kErrorFeatures = 5;

/// The fields' error model: with p = log(positions / 1090), d = log(directions / 16) and o =
/// log(ao_occluded + 0.01), log(RMS) = log(probe) + c0 p + c1 d + c2 p d + c3 d o + c4 p o, RMS of the
/// AO image on the 0-255 scale against the exact one with the same rays, `probe` that of kFieldProbe on
/// the same scene (SceneProfile::field_probe_rms): the probe's own RMS is measured, the others' predicted.
struct FieldErrorModel {
  std::array<double, kErrorFeatures> coefficients{};  ///< c0..c4.
  double sigma = 0.0;                    ///< Spread of the fit's residuals in log RMS: 1.4826 x their median absolute deviation.
  std::size_t samples = 0;               ///< Measurements fitted (0: no model; fields are never planned).

  /// The fit's RMS for a field of `positions` x `directions`^2 on a scene whose AO rays are
  /// `ao_occluded` and whose probe measured `probe_rms`.
  double predict(int positions, int directions, double ao_occluded, double probe_rms) const;
  /// The RMS the fit says is not exceeded nine times in ten: predict() times exp(1.2816 sigma) (the
  /// probe's measured RMS for the probe itself).
  double bound(int positions, int directions, double ao_occluded, double probe_rms) const;
  /// The lowest RMS the fit does not rule out: predict() times exp(-2.5 sigma) (an RMS within it less
  /// than once in 160 times; the probe's measured RMS for the probe itself).
  double optimistic(int positions, int directions, double ao_occluded, double probe_rms) const;

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const FieldErrorModel&) const = default;
};

/// The planner's calibrated model: constants per candidate (plan_candidates() order) for the threads
/// they were measured on, and the field error model.
struct PlanModel {
  int threads = 1;                               ///< Threads the constants were measured with.
  std::vector<CandidateConstants> constants;     ///< One per candidate.
  FieldErrorModel field_error;

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const PlanModel&) const = default;
};

/// One candidate measured on one scene.
struct CandidateMeasurement {
  std::string spec;                          ///< The candidate's spec.
  double build_ms = 0.0;                     ///< Median build time.
  std::uint64_t memory_bytes = 0;            ///< Bytes it holds.
  std::array<double, kPlanKinds> ray_us{};   ///< Per kind, microseconds per ray (wall time of a batch on the threads); < 0 = not measured.
  double update_ms = -1.0;                   ///< One in-place object update and commit; < 0 = not updatable or not measured.
  double ao_rms = 0.0;                       ///< Fields: RMS (0-255) of its AO image against the exact one; exact candidates 0.

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const CandidateMeasurement&) const = default;
};

/// Everything the planner's calibration measures on one scene.
struct PlanMeasurement {
  SceneProfile profile;
  std::vector<CandidateMeasurement> candidates;  ///< Those built (others exceeded a limit).

  /// The measurement of `spec`, or nullptr.
  const CandidateMeasurement* find(std::string_view spec) const;

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const PlanMeasurement&) const = default;
};

/// Fits the model on `scenes[i]` for i in `subset` (at least one): each constant is the geometric
/// mean of measured / feature over the scenes that measured it (the grid's and brute force's per-ray
/// costs: a power law, least squares in log space, over at least two distinct features); the error
/// model is least squares over every field measurement of a probed scene (no model below 6 of them).
/// Per-ray constants are for `threads`.
PlanModel fit_plan_model(std::span<const PlanMeasurement> scenes, std::span<const std::size_t> subset, int threads);

/// What the workload needs.
struct PlanRequest {
  double rays = 1e6;                 ///< R, rays of `kind`.
  RayKind kind = RayKind::path;      ///< Their kind.
  double max_error = 0.0;            ///< E, RMS (0-255) of an AO image allowed; 0 = exact structures only.
  double updates = 0.0;              ///< U, object updates (moves) over the workload.
  double max_memory = std::numeric_limits<double>::infinity();  ///< Bytes a build may take.
};

/// Throws vf::Error naming the bad field unless rays >= 1, 0 <= max_error <= 255, updates >= 0 and
/// max_memory > 0 (all finite but max_memory).
void validate_plan_request(const PlanRequest& request);

/// One candidate as the planner predicted it.
struct PlanRow {
  std::string spec;
  double build_ms = 0.0;     ///< Predicted build.
  double ray_us = 0.0;       ///< Predicted microseconds per ray on the threads in force.
  double update_ms = 0.0;    ///< Predicted time of one update (in place, or a rebuild).
  double total_ms = 0.0;     ///< build + R rays + U updates.
  double bytes = 0.0;        ///< Peak bytes of its build (the registry's estimate).
  double error = 0.0;        ///< Predicted RMS bound, or the measured RMS (fields; 0 for exact candidates).
  bool error_measured = false;  ///< `error` is the field's measured RMS (the probe's, or a settled plan's).
  bool measurable = false;   ///< A field out on its bound alone that the fit cannot rule out (FieldErrorModel::optimistic <= the error).
  std::string excluded;      ///< Why it cannot be chosen; empty when it can.
};

/// The candidates weighed and the choice.
inline constexpr std::size_t kNoRow = std::numeric_limits<std::size_t>::max();

struct Plan {
  std::vector<PlanRow> rows;     ///< Every candidate, table order.
  std::size_t chosen = kNoRow;   ///< Index in rows of the winner.
  /// A measurable field (its 90% bound is over the error, its optimistic RMS is not: the model cannot
  /// tell) predicted faster than the choice by more than its build, the fastest such:
  /// measuring its RMS settles it (settle_plan). kNoRow when none.
  std::size_t to_measure = kNoRow;
  std::string reason;            ///< Why it won, one line.
};

/// Predicts every candidate for `profile` and `request` with `model` (per-ray times rescaled from
/// model.threads to `threads`), `bytes_of(spec)` giving each build's peak bytes, and picks the lowest
/// total among those that answer the kind, fit max_memory and stay within max_error. Throws
/// vf::Error on a bad request or when no candidate qualifies.
Plan make_plan(const PlanModel& model, const SceneProfile& profile, const PlanRequest& request, int threads,
               const std::function<double(std::string_view spec)>& bytes_of);

/// Settles plan.to_measure with its measured AO image RMS `measured_rms` (the probe's measure: the AO
/// image against the exact one): within request.max_error it becomes the choice, else it is excluded
/// with its measurement; to_measure becomes the next field worth measuring against the (new) choice,
/// and the reason is rewritten. Nothing when to_measure is kNoRow.
void settle_plan(Plan& plan, double measured_rms, const PlanRequest& request);

/// The smallest field (positions x directions^2 cells) of the candidates whose error bound for a scene
/// with `profile` (probed) is at most `target_rms`, or, given `measure` (the measured RMS of candidate
/// i), a smaller one whose measured RMS is within it: fields are tried smallest first, measuring those
/// whose optimistic RMS is within `target_rms` and whose bound is not. Its index in
/// plan_candidates(); npos when none is, or the scene was not probed.
std::size_t field_for_target_rms(const FieldErrorModel& model, const SceneProfile& profile, double target_rms,
                                 const std::function<double(std::size_t candidate)>& measure = {});

/// Measured total of candidate `m` for R rays of `kind` and U updates: build + R t_R + U t_U
/// (t_U = a rebuild when it is not updatable); +infinity when it did not measure `kind`.
double measured_total_ms(const CandidateMeasurement& m, RayKind kind, double rays, double updates);

}  // namespace vf
