#include "visfield/select/plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <utility>

#include "visfield/core/error.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/text.hpp"
#include "visfield/select/calibration.hpp"

namespace vf {
namespace {

// The structures and the parameter choices weighed. Fields come in three positional and three
// directional resolutions (the calibration measures each, so the error model's choices can be
// checked against measured errors); the other structures at their defaults, BeamField also at a
// quarter of its directions and tiles (4x faster to build, a sixteenth of the memory).
constexpr PlanCandidate kCandidates[] = {
    {"grid:levels=1", CostShape::grid, false},
    {"kdtree:levels=1", CostShape::tree, false},
    {"bvh:levels=1", CostShape::tree, false},
    {"bvh:levels=2", CostShape::two_level, true},
    {"median-bsp:levels=1", CostShape::tree, false},
    {"beam", CostShape::beam, true},
    {"beam:dirs=129,n=32", CostShape::beam, true},
    {"brute:levels=1", CostShape::brute, false},
    {"field:positions=1090,directions=16", CostShape::field, false, 1090, 16},
    {"field:positions=1090,directions=32", CostShape::field, false, 1090, 32},
    {"field:positions=1090,directions=64", CostShape::field, false, 1090, 64},
    {"field:positions=4226,directions=16", CostShape::field, false, 4226, 16},
    {"field:positions=4226,directions=32", CostShape::field, false, 4226, 32},
    {"field:positions=4226,directions=64", CostShape::field, false, 4226, 64},
    {"field:positions=16642,directions=16", CostShape::field, false, 16642, 16},
    {"field:positions=16642,directions=32", CostShape::field, false, 16642, 32},
    {"field:positions=16642,directions=64", CostShape::field, false, 16642, 64},
};

double n_log_n(double n) { return std::max(n, 1.0) * cost_log2(static_cast<std::uint64_t>(n)); }

double field_cells(const PlanCandidate& c) { return static_cast<double>(c.positions) * c.directions * c.directions; }

// Geometric mean of the positive values (0 when there are none).
double geometric_mean(const std::vector<double>& values) {
  double sum = 0.0;
  std::size_t n = 0;
  for (double v : values)
    if (v > 0.0 && std::isfinite(v)) sum += std::log(v), ++n;
  return n == 0 ? 0.0 : std::exp(sum / static_cast<double>(n));
}

// The error model's features for a field of `positions` x `directions`^2: log positions and log
// directions against the probe's, their product, and each times log (AO occluded + 0.01). All are 0 at
// the probe itself, whose RMS is measured; the products let the gain of finer directions depend on the
// positions and on how enclosed the scene is.
std::array<double, kErrorFeatures> error_features(int positions, int directions, double ao_occluded) {
  const double lp = std::log(static_cast<double>(positions) / kFieldProbePositions);
  const double ld = std::log(static_cast<double>(directions) / kFieldProbeDirections);
  const double lo = std::log(std::clamp(ao_occluded, 0.0, 1.0) + 0.01);
  return {lp, ld, lp * ld, ld * lo, lp * lo};
}

bool is_probe(int positions, int directions) { return positions == kFieldProbePositions && directions == kFieldProbeDirections; }

// Whether a candidate's per-ray cost is a fitted power of its feature (a measured time, or N with
// caches that stop holding the triangles) rather than proportional to it.
bool power_law(const PlanCandidate& c) { return c.shape == CostShape::grid || c.shape == CostShape::brute; }

// The largest power of a feature the cost model fits (fit_power).
constexpr double kMostExponent = 4.0;

// Coefficient and exponent of t = c f^e by least squares on (log f, log t); e = 1 (the geometric mean)
// when the features do not spread. e is kept in [0, kMostExponent]: the grid's time follows its
// sample's with a power near 1 and brute force's N with one just over 1, while a fit over two scenes
// whose samples nearly agree can swing far off (-8.5 with two small scenes timed under ASan).
std::pair<double, double> fit_power(const std::vector<double>& f, const std::vector<double>& t) {
  double mf = 0.0, mt = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) mf += std::log(f[i]), mt += std::log(t[i]);
  mf /= static_cast<double>(f.size()), mt /= static_cast<double>(f.size());
  double sff = 0.0, sft = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    sff += (std::log(f[i]) - mf) * (std::log(f[i]) - mf);
    sft += (std::log(f[i]) - mf) * (std::log(t[i]) - mt);
  }
  const double e = sff > 1e-6 ? std::clamp(sft / sff, 0.0, kMostExponent) : 1.0;
  return {std::exp(mt - e * mf), e};
}

// Least squares by the normal equations (Gaussian elimination with partial pivoting; a tiny ridge keeps
// a degenerate design, such as one positional resolution only, solvable).
std::array<double, kErrorFeatures> least_squares(const std::vector<std::array<double, kErrorFeatures>>& x, const std::vector<double>& y) {
  constexpr int n = static_cast<int>(kErrorFeatures);
  double a[n][n + 1] = {};
  for (std::size_t s = 0; s < x.size(); ++s)
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) a[i][j] += x[s][i] * x[s][j];
      a[i][n] += x[s][i] * y[s];
    }
  for (int i = 0; i < n; ++i) a[i][i] += 1e-9 * (1.0 + a[i][i]);
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r)
      if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
    for (int k = 0; k <= n; ++k) std::swap(a[col][k], a[pivot][k]);
    for (int r = 0; r < n; ++r) {
      if (r == col || a[col][col] == 0.0) continue;
      const double f = a[r][col] / a[col][col];
      for (int k = col; k <= n; ++k) a[r][k] -= f * a[col][k];
    }
  }
  std::array<double, kErrorFeatures> beta{};
  for (int i = 0; i < n; ++i) beta[i] = a[i][i] != 0.0 ? a[i][n] / a[i][i] : 0.0;
  return beta;
}

// The log RMS a field error measurement counts as (an RMS of 0 would have no logarithm).
constexpr double kLeastRms = 0.01;
// The z of the one-sided 90% quantile of a normal distribution.
constexpr double kNinetyPercentZ = 1.2816;
// A field whose fit times exp(-2.5 sigma) is over E is ruled out (its RMS is within E less than once in
// 160 times); one between that and its 90% bound is worth measuring (when it would save the planner
// more than its build). (Leave-one-out over the built-in calibration: 1.28 sigma here left a worst regret of 4.8, a
// scene whose one field within E measured 1.9 sigma below its fit; 2.5 sigma, 1.9.)
constexpr double kRuleOutZ = 2.5;
// The standard deviation of normal residuals over their median absolute deviation.
constexpr double kMadToSigma = 1.4826;

// Writes plan.reason: why the choice won, and what measuring plan.to_measure could change.
void explain(Plan& plan, const PlanRequest& request);

// The measurable field, not measured yet, with the lowest total that beats the choice by more than its
// build: measuring costs that build (and a small AO image), lost when it fails. kNoRow when none.
std::size_t next_to_measure(const Plan& plan) {
  std::size_t next = kNoRow;
  for (std::size_t i = 0; i < plan.rows.size(); ++i) {
    const PlanRow& row = plan.rows[i];
    if (row.measurable && !row.error_measured && row.total_ms + row.build_ms < plan.rows[plan.chosen].total_ms &&
        (next == kNoRow || row.total_ms < plan.rows[next].total_ms))
      next = i;
  }
  return next;
}

// Below this many field measurements the error model is not fitted.
constexpr std::size_t kLeastErrorSamples = 6;

}  // namespace

std::span<const PlanCandidate> plan_candidates() { return kCandidates; }

std::size_t plan_candidate_index(std::string_view spec) {
  for (std::size_t i = 0; i < std::size(kCandidates); ++i)
    if (kCandidates[i].spec == spec) return i;
  return static_cast<std::size_t>(-1);
}

std::size_t plan_kind_index(RayKind kind) {
  for (std::size_t i = 0; i < kRayKinds.size(); ++i)
    if (kRayKinds[i] == kind) return i;
  return 0;
}

double build_feature(const PlanCandidate& c, const SceneProfile& p) {
  const double n = static_cast<double>(p.triangles), u = static_cast<double>(p.unique_triangles),
               o = static_cast<double>(p.objects);
  switch (c.shape) {
    case CostShape::grid: return p.grid_build_ms;
    case CostShape::brute: return std::max(n, 1.0);
    case CostShape::tree:
    case CostShape::beam: return n_log_n(n);
    case CostShape::two_level: return n_log_n(u) + n_log_n(o);
    case CostShape::field: return field_cells(c) * std::max(p.mesh_log2_sum, 1.0);
  }
  return 1.0;
}

double ray_feature(const PlanCandidate& c, const SceneProfile& p, RayKind kind) {
  const std::size_t k = plan_kind_index(kind);
  switch (c.shape) {
    case CostShape::grid: return p.grid_sample_us[k];
    case CostShape::tree:
      return p.bvh_sample_us[k] * cost_log2(p.triangles) / (cost_log2(p.unique_triangles) + cost_log2(p.objects));
    case CostShape::two_level: return p.bvh_sample_us[k];
    case CostShape::beam: return cost_log2(p.triangles);
    case CostShape::brute: return static_cast<double>(std::max<std::uint64_t>(p.triangles, 1));
    case CostShape::field: return cost_log2(p.objects);
  }
  return 1.0;
}

double update_feature(const PlanCandidate& c, const SceneProfile& p) {
  const double o = static_cast<double>(std::max<std::uint64_t>(p.objects, 1));
  if (c.shape == CostShape::two_level) return n_log_n(o);
  if (c.shape == CostShape::beam) return std::max(static_cast<double>(p.triangles) / o, 1.0);
  return 1.0;
}

double FieldErrorModel::predict(int positions, int directions, double ao_occluded, double probe_rms) const {
  if (is_probe(positions, directions)) return probe_rms;
  const std::array<double, kErrorFeatures> x = error_features(positions, directions, ao_occluded);
  double log_rms = std::log(std::max(probe_rms, kLeastRms));
  for (std::size_t i = 0; i < kErrorFeatures; ++i) log_rms += coefficients[i] * x[i];
  return std::exp(log_rms);
}

double FieldErrorModel::bound(int positions, int directions, double ao_occluded, double probe_rms) const {
  const double rms = predict(positions, directions, ao_occluded, probe_rms);
  return is_probe(positions, directions) ? rms : rms * std::exp(kNinetyPercentZ * sigma);
}

double FieldErrorModel::optimistic(int positions, int directions, double ao_occluded, double probe_rms) const {
  const double rms = predict(positions, directions, ao_occluded, probe_rms);
  return is_probe(positions, directions) ? rms : rms * std::exp(-kRuleOutZ * sigma);
}

const CandidateMeasurement* PlanMeasurement::find(std::string_view spec) const {
  for (const CandidateMeasurement& m : candidates)
    if (m.spec == spec) return &m;
  return nullptr;
}

PlanModel fit_plan_model(std::span<const PlanMeasurement> scenes, std::span<const std::size_t> subset, int threads) {
  if (subset.empty()) throw Error("plan: no calibration scenes to fit the model on");
  PlanModel model;
  model.threads = std::max(threads, 1);
  std::vector<std::array<double, kErrorFeatures>> x;
  std::vector<double> y;
  for (const PlanCandidate& c : kCandidates) {
    std::vector<double> build, update;
    std::array<std::vector<double>, kPlanKinds> features, times;
    for (std::size_t s : subset) {
      if (s >= scenes.size()) throw Error("plan: scene index " + std::to_string(s) + " out of range");
      const PlanMeasurement& scene = scenes[s];
      const CandidateMeasurement* m = scene.find(c.spec);
      if (!m) continue;
      const double bf = build_feature(c, scene.profile);
      if (bf > 0.0) build.push_back(m->build_ms / bf);
      if (c.updatable && m->update_ms > 0.0) update.push_back(m->update_ms / update_feature(c, scene.profile));
      for (std::size_t k = 0; k < kPlanKinds; ++k) {
        const double feature = ray_feature(c, scene.profile, kRayKinds[k]);
        if (m->ray_us[k] > 0.0 && feature > 0.0) features[k].push_back(feature), times[k].push_back(m->ray_us[k]);
      }
      // The probe's own row says nothing: its RMS is the profile's, measured.
      if (c.approximate() && scene.profile.field_probe_rms >= 0.0 && !is_probe(c.positions, c.directions)) {
        x.push_back(error_features(c.positions, c.directions, scene.profile.ao_occluded));
        y.push_back(std::log(std::max(m->ao_rms, kLeastRms)) - std::log(std::max(scene.profile.field_probe_rms, kLeastRms)));
      }
    }
    CandidateConstants k;
    k.build_ms = geometric_mean(build);
    k.update_ms = geometric_mean(update);
    for (std::size_t kind = 0; kind < kPlanKinds; ++kind) {
      if (features[kind].empty()) continue;
      if (power_law(c)) {
        std::tie(k.ray_us[kind], k.ray_exponent[kind]) = fit_power(features[kind], times[kind]);
      } else {
        std::vector<double> ratios;
        for (std::size_t i = 0; i < features[kind].size(); ++i) ratios.push_back(times[kind][i] / features[kind][i]);
        k.ray_us[kind] = geometric_mean(ratios);
      }
    }
    model.constants.push_back(k);
  }
  if (x.size() >= kLeastErrorSamples) {
    FieldErrorModel& e = model.field_error;
    e.coefficients = least_squares(x, y);
    e.samples = x.size();
    // A robust sigma: 1.4826 x the median absolute deviation of the residuals (the standard deviation
    // for normal residuals), so that one defective field far off the fit does not loosen every bound.
    std::vector<double> residuals;
    for (std::size_t s = 0; s < x.size(); ++s) {
      double fit = 0.0;
      for (std::size_t i = 0; i < kErrorFeatures; ++i) fit += e.coefficients[i] * x[s][i];
      residuals.push_back(y[s] - fit);
    }
    const double centre = median(residuals);
    for (double& r : residuals) r = std::fabs(r - centre);
    e.sigma = kMadToSigma * median(residuals);
  }
  return model;
}

void validate_plan_request(const PlanRequest& r) {
  if (!(r.rays >= 1.0) || !std::isfinite(r.rays)) throw Error("plan: rays must be a finite number >= 1, got " + std::to_string(r.rays));
  if (!(r.max_error >= 0.0 && r.max_error <= 255.0))
    throw Error("plan: error must be an RMS in 0..255, got " + std::to_string(r.max_error));
  if (!(r.updates >= 0.0) || !std::isfinite(r.updates))
    throw Error("plan: updates must be a finite number >= 0, got " + std::to_string(r.updates));
  if (!(r.max_memory > 0.0)) throw Error("plan: the memory limit must be > 0 bytes");
}

Plan make_plan(const PlanModel& model, const SceneProfile& profile, const PlanRequest& request, int threads,
               const std::function<double(std::string_view spec)>& bytes_of) {
  validate_plan_request(request);
  if (model.constants.size() != std::size(kCandidates))
    throw Error("plan: the calibration holds " + std::to_string(model.constants.size()) + " candidates, this build weighs " +
                std::to_string(std::size(kCandidates)));
  const std::size_t k = plan_kind_index(request.kind);
  const double thread_ratio = static_cast<double>(model.threads) / std::max(threads, 1);
  const double sample_ratio = static_cast<double>(std::max(profile.threads, 1)) / std::max(threads, 1);
  Plan plan;
  for (std::size_t i = 0; i < std::size(kCandidates); ++i) {
    const PlanCandidate& c = kCandidates[i];
    const CandidateConstants& constants = model.constants[i];
    PlanRow row;
    row.spec = std::string(c.spec);
    const double rf = ray_feature(c, profile, request.kind);
    row.build_ms = constants.build_ms * build_feature(c, profile);
    row.ray_us = constants.ray_us[k] * std::pow(rf, constants.ray_exponent[k]) * (c.shape == CostShape::grid ? sample_ratio : thread_ratio);
    row.update_ms = c.updatable && constants.update_ms > 0.0 ? constants.update_ms * update_feature(c, profile) : row.build_ms;
    row.total_ms = row.build_ms + request.rays * row.ray_us / 1000.0 + request.updates * row.update_ms;
    row.bytes = bytes_of(c.spec);
    double optimistic_error = 0.0;
    if (c.approximate() && model.field_error.samples > 0 && profile.field_probe_rms >= 0.0) {
      row.error = model.field_error.bound(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms);
      optimistic_error = model.field_error.optimistic(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms);
      row.error_measured = c.spec == kFieldProbe;
    }
    if (!c.answers(request.kind))
      row.excluded = "answers occlusion (ao, shadow) rays only";
    else if (constants.build_ms <= 0.0 || constants.ray_us[k] <= 0.0)
      row.excluded = "not calibrated for " + std::string(ray_kind_name(request.kind)) + " rays";
    else if (rf <= 0.0)
      row.excluded = c.shape == CostShape::grid ? "no grid sample of this scene (too large to flatten for it)"
                                                : "no BVH sample of " + std::string(ray_kind_name(request.kind)) + " rays in the profile";
    else if (c.approximate() && request.max_error <= 0.0)
      row.excluded = "approximate; error=0 allows exact structures only";
    else if (c.approximate() && model.field_error.samples == 0)
      row.excluded = "no field error model in the calibration";
    else if (c.approximate() && profile.field_probe_rms < 0.0)
      row.excluded = "the scene was not probed with a field";
    else if (c.approximate() && row.error > request.max_error) {
      row.excluded = (row.error_measured ? "measured RMS " : "predicted RMS ") + formatted("%.2f", row.error) + " > error " +
                     formatted("%g", request.max_error);
      row.measurable = optimistic_error <= request.max_error && row.bytes <= request.max_memory;
    }
    else if (row.bytes > request.max_memory)
      row.excluded = "needs " + formatted("%.3g", row.bytes / (1024.0 * 1024.0)) + " MiB, over the memory limit";
    if (row.excluded.empty() && (plan.chosen == kNoRow || row.total_ms < plan.rows[plan.chosen].total_ms))
      plan.chosen = plan.rows.size();
    plan.rows.push_back(std::move(row));
  }
  if (plan.chosen == kNoRow)
    throw Error("plan: no structure fits this workload (every candidate is excluded: see `visfield select`)");
  plan.to_measure = next_to_measure(plan);
  explain(plan, request);
  return plan;
}

void settle_plan(Plan& plan, double measured_rms, const PlanRequest& request) {
  if (plan.to_measure == kNoRow) return;
  PlanRow& row = plan.rows[plan.to_measure];
  row.error = measured_rms;
  row.error_measured = true;
  if (measured_rms <= request.max_error) {
    row.excluded.clear();
    plan.chosen = plan.to_measure;
  } else {
    row.excluded = "measured RMS " + formatted("%.2f", measured_rms) + " > error " + formatted("%g", request.max_error);
  }
  plan.to_measure = next_to_measure(plan);
  explain(plan, request);
}

namespace {

void explain(Plan& plan, const PlanRequest& request) {
  const PlanRow& win = plan.rows[plan.chosen];
  std::size_t runner = kNoRow;
  for (std::size_t i = 0; i < plan.rows.size(); ++i)
    if (i != plan.chosen && plan.rows[i].excluded.empty() &&
        (runner == kNoRow || plan.rows[i].total_ms < plan.rows[runner].total_ms))
      runner = i;
  plan.reason = "lowest predicted total, " + formatted("%.4g", win.total_ms) + " ms (build " + formatted("%.4g", win.build_ms) +
                " + rays " + formatted("%.4g", request.rays * win.ray_us / 1000.0) + " + updates " +
                formatted("%.4g", request.updates * win.update_ms) + ")";
  if (runner != kNoRow)
    plan.reason += "; next " + plan.rows[runner].spec + " at " + formatted("%.4g", plan.rows[runner].total_ms) + " ms (" +
                   formatted("%.2f", plan.rows[runner].total_ms / std::max(win.total_ms, 1e-12)) + "x)";
  if (win.error_measured && win.spec != kFieldProbe) plan.reason += "; its RMS measured " + formatted("%.2f", win.error);
  if (plan.to_measure != kNoRow)
    plan.reason += "; " + plan.rows[plan.to_measure].spec + " would be faster (" + formatted("%.4g", plan.rows[plan.to_measure].total_ms) +
                   " ms) if its RMS, predicted within the error but not its bound, were measured";
}

}  // namespace

std::size_t field_for_target_rms(const FieldErrorModel& model, const SceneProfile& profile, double target_rms,
                                 const std::function<double(std::size_t candidate)>& measure) {
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  if (model.samples == 0 || profile.field_probe_rms < 0.0) return kNone;
  std::vector<std::size_t> fields;
  for (std::size_t i = 0; i < std::size(kCandidates); ++i)
    if (kCandidates[i].approximate()) fields.push_back(i);
  std::stable_sort(fields.begin(), fields.end(),
                   [](std::size_t a, std::size_t b) { return field_cells(kCandidates[a]) < field_cells(kCandidates[b]); });
  for (std::size_t i : fields) {
    const PlanCandidate& c = kCandidates[i];
    if (model.bound(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms) <= target_rms) return i;
    if (measure && model.optimistic(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms) <= target_rms &&
        measure(i) <= target_rms)
      return i;
  }
  return kNone;
}

double measured_total_ms(const CandidateMeasurement& m, RayKind kind, double rays, double updates) {
  const double ray_us = m.ray_us[plan_kind_index(kind)];
  if (ray_us < 0.0) return std::numeric_limits<double>::infinity();
  return m.build_ms + rays * ray_us / 1000.0 + updates * (m.update_ms >= 0.0 ? m.update_ms : m.build_ms);
}

}  // namespace vf
