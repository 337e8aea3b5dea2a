#include "visfield/select/critical_rays.hpp"

#include <cmath>
#include <limits>

namespace vf {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kUsPerMs = 1000.0;

}  // namespace

double estimated_critical_rays(double tree_build_ms, double grid_ray_us, double tree_ray_us, double epsilon) {
  // Step 5: a hierarchy that is no faster per ray never pays off. Otherwise epsilon only enlarges an
  // already positive denominator.
  if (!(grid_ray_us > tree_ray_us)) return kInfinity;
  const double denominator_us = grid_ray_us * (1.0 + epsilon) - tree_ray_us;
  if (!(denominator_us > 0.0)) return kInfinity;
  return tree_build_ms * kUsPerMs / denominator_us;
}

double exact_critical_rays(double grid_build_ms, double tree_build_ms, double grid_ray_us, double tree_ray_us) {
  const double saved_per_ray_us = grid_ray_us - tree_ray_us;
  if (!(saved_per_ray_us > 0.0)) return kInfinity;
  return std::fmax(0.0, (tree_build_ms - grid_build_ms) * kUsPerMs / saved_per_ray_us);
}

double exact_critical_rays(const SceneMeasurement& scene, RayKind kind) {
  const RayTimings& t = scene.timings(kind);
  return exact_critical_rays(scene.grid_build_ms, scene.tree_build_ms, t.grid_us, t.tree_us);
}

double estimated_tree_build_ms(const CalibrationConstants& constants, std::uint64_t triangles) {
  return constants.build_ms_per_n_log2_n * static_cast<double>(triangles) * cost_log2(triangles);
}

double estimated_tree_ray_us(const CalibrationConstants& constants, RayKind kind, std::uint64_t triangles) {
  return constants.ray_us(kind) * cost_log2(triangles);
}

double estimated_critical_rays(const CalibrationConstants& constants, RayKind kind, std::uint64_t triangles,
                               double grid_sample_us, double epsilon) {
  return estimated_critical_rays(estimated_tree_build_ms(constants, triangles), grid_sample_us,
                                 estimated_tree_ray_us(constants, kind, triangles), epsilon);
}

bool grid_wins(double rays, double critical_rays) { return rays < critical_rays; }

double estimate_error_percent(double estimate, double exact) {
  if (!std::isfinite(estimate) || !std::isfinite(exact) || exact == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return 100.0 * (estimate - exact) / exact;
}

}  // namespace vf
