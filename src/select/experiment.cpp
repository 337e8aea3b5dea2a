#include "visfield/select/experiment.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "visfield/core/error.hpp"
#include "visfield/core/rng.hpp"

namespace vf {
namespace {

void require_two_scenes(std::span<const SceneMeasurement> scenes, const char* what) {
  if (scenes.size() < 2)
    throw Error(std::string(what) + ": needs at least 2 measured scenes, got " + std::to_string(scenes.size()));
}

// Uniform integer in [0, n) for n >= 1 (Lemire's multiply-shift; the bias is below 2^-32 * n).
std::size_t uniform_below(Rng& rng, std::size_t n) {
  return static_cast<std::size_t>((static_cast<std::uint64_t>(rng.next_u32()) * n) >> 32);
}

}  // namespace

CalibrationConstants constants_without(std::span<const SceneMeasurement> scenes, std::size_t left_out) {
  std::vector<std::size_t> others;
  for (std::size_t i = 0; i < scenes.size(); ++i)
    if (i != left_out) others.push_back(i);
  return compute_constants(scenes, others);
}

std::vector<CriticalRaysEstimate> leave_one_out(std::span<const SceneMeasurement> scenes, RayKind kind, double epsilon) {
  require_two_scenes(scenes, "leave-one-out");
  std::vector<CriticalRaysEstimate> rows;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    CriticalRaysEstimate row;
    row.exact = exact_critical_rays(scenes[i], kind);
    row.estimate = estimated_critical_rays(constants_without(scenes, i), kind, scenes[i].triangles,
                                           scenes[i].timings(kind).grid_sample_us, epsilon);
    row.error_percent = estimate_error_percent(row.estimate, row.exact);
    rows.push_back(row);
  }
  return rows;
}

std::vector<LeaveKOutRow> leave_k_out(std::span<const SceneMeasurement> scenes, RayKind kind, std::size_t splits,
                                      std::uint64_t seed, double epsilon) {
  require_two_scenes(scenes, "leave-k-out");
  if (splits < 1) throw Error("leave-k-out: needs at least 1 split per k");
  const std::size_t n = scenes.size();
  std::vector<double> exact(n);
  for (std::size_t i = 0; i < n; ++i) exact[i] = exact_critical_rays(scenes[i], kind);
  std::vector<LeaveKOutRow> rows;
  for (std::size_t k = 1; k < n; ++k) {
    LeaveKOutRow row;
    row.k = k;
    row.splits = splits;
    double sum = 0.0, sum_abs = 0.0;
    for (std::size_t split = 0; split < splits; ++split) {
      std::vector<std::size_t> order(n);
      std::iota(order.begin(), order.end(), std::size_t{0});
      Rng rng(seed, k, split);
      for (std::size_t i = n - 1; i > 0; --i) std::swap(order[i], order[uniform_below(rng, i + 1)]);
      const std::span<const std::size_t> calibration(order.data(), k);
      const CalibrationConstants constants = compute_constants(scenes, calibration);
      for (std::size_t j = k; j < n; ++j) {
        const SceneMeasurement& scene = scenes[order[j]];
        const double estimate =
            estimated_critical_rays(constants, kind, scene.triangles, scene.timings(kind).grid_sample_us, epsilon);
        const double error = estimate_error_percent(estimate, exact[order[j]]);
        if (std::isnan(error)) {
          ++row.undefined;
          continue;
        }
        ++row.estimates;
        sum += error;
        sum_abs += std::fabs(error);
      }
    }
    const double count = static_cast<double>(row.estimates);
    row.mean_error_percent = row.estimates ? sum / count : std::numeric_limits<double>::quiet_NaN();
    row.mean_abs_error_percent = row.estimates ? sum_abs / count : std::numeric_limits<double>::quiet_NaN();
    rows.push_back(row);
  }
  return rows;
}

double grid_total_ms(const SceneMeasurement& scene, RayKind kind, double rays) {
  return scene.grid_build_ms + rays * scene.timings(kind).grid_us / 1000.0;
}

double tree_total_ms(const SceneMeasurement& scene, RayKind kind, double rays) {
  return scene.tree_build_ms + rays * scene.timings(kind).tree_us / 1000.0;
}

std::vector<DecisionRow> decision_accuracy(std::span<const SceneMeasurement> scenes, RayKind kind,
                                           std::span<const double> ray_counts, double epsilon) {
  const std::vector<CriticalRaysEstimate> estimates = leave_one_out(scenes, kind, epsilon);
  std::vector<DecisionRow> rows;
  for (double rays : ray_counts) {
    DecisionRow row;
    row.rays = rays;
    row.scenes = scenes.size();
    double ratio_sum = 0.0;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      const double grid = grid_total_ms(scenes[i], kind, rays);
      const double tree = tree_total_ms(scenes[i], kind, rays);
      const bool picks_grid = grid_wins(rays, estimates[i].estimate);
      row.grid_right += grid <= tree;
      row.tree_right += tree <= grid;
      row.right += picks_grid ? grid <= tree : tree <= grid;
      const double decision = picks_grid ? grid : scenes[i].grid_build_ms + tree;
      const double best = std::fmin(grid, tree);
      ratio_sum += best > 0.0 ? decision / best : 1.0;
    }
    row.mean_time_ratio = ratio_sum / static_cast<double>(scenes.size());
    rows.push_back(row);
  }
  return rows;
}

}  // namespace vf
