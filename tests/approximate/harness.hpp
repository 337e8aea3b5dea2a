#pragma once
/// \file The harness for approximate structures: measure their answers against an exact structure on
/// the same rays, and check what was measured against the bounds the structure states
/// (ErrorBounds). Exact structures are checked by tests/differential instead, for equality.

#include <cmath>
#include <cstdint>
#include <span>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "visfield/accel/query.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/compare.hpp"

namespace vf::test {

/// The error of an approximate structure against an exact one, over one ray set.
struct ApproximationError {
  std::size_t rays = 0;
  std::size_t both_hit = 0;                ///< Rays both structures hit (the distance statistics are over these).
  double occlusion_disagreement = 0.0;     ///< Fraction of rays whose occluded() answers differ.
  double hit_disagreement = 0.0;           ///< Fraction of rays one structure hits and the other misses (closest-hit role).
  double distance_rms = 0.0;               ///< RMS of |t - t_exact| |dir| / diameter over both_hit rays.
  double distance_max = 0.0;               ///< Largest |t - t_exact| |dir| / diameter.
  double image_rms = 0.0;                  ///< RMS difference of an AO image, when one was rendered.
};

/// Measures `approximate` against `exact` on `rays`; distances are divided by `diameter` (the scene's
/// bounding-sphere diameter). The closest-hit figures are measured when `approximate` answers that
/// role; otherwise they stay 0.
template <OcclusionQuery A, Accelerator E>
ApproximationError measure_approximation(const A& approximate, const E& exact, std::span<const Ray> rays,
                                         double diameter) {
  ApproximationError e;
  e.rays = rays.size();
  std::size_t occlusion_wrong = 0, hit_wrong = 0;
  double sum_sq = 0.0;
  for (const Ray& ray : rays) {
    occlusion_wrong += approximate.occluded(ray) != exact.occluded(ray) ? 1 : 0;
    if constexpr (ClosestHitQuery<A>) {
      const Hit got = approximate.intersect(ray), expected = exact.intersect(ray);
      if (got.found != expected.found) {
        ++hit_wrong;
      } else if (got) {
        ++e.both_hit;
        const double d = std::fabs(static_cast<double>(got.t) - expected.t) * length(ray.dir) / diameter;
        sum_sq += d * d;
        e.distance_max = std::max(e.distance_max, d);
      }
    }
  }
  const auto n = static_cast<double>(std::max<std::size_t>(rays.size(), 1));
  e.occlusion_disagreement = static_cast<double>(occlusion_wrong) / n;
  e.hit_disagreement = static_cast<double>(hit_wrong) / n;
  e.distance_rms = e.both_hit > 0 ? std::sqrt(sum_sq / static_cast<double>(e.both_hit)) : 0.0;
  return e;
}

/// RMS difference between the AO images rendered with `approximate` and with `exact` as the occluder
/// (camera rays through `exact` for both, so the images differ by the occlusion answers alone).
template <OcclusionQuery A, Accelerator E>
double ao_image_rms(const A& approximate, const E& exact, const Scene& scene, const Camera& camera, AoOptions options) {
  options.progress = false;
  return compare_images(render_ao(exact, approximate, scene, camera, options), render_ao(exact, exact, scene, camera, options))
      .rms;
}

/// Success when every measured error is within the stated bound; otherwise a failure naming each
/// bound exceeded with both values.
inline ::testing::AssertionResult within_bounds(const ApproximationError& e, const ErrorBounds& bounds) {
  std::ostringstream exceeded;
  const auto check = [&](const char* what, double measured, double bound) {
    if (measured > bound) exceeded << " " << what << " " << measured << " > " << bound << ";";
  };
  check("occlusion disagreement", e.occlusion_disagreement, bounds.occlusion_disagreement);
  check("hit disagreement", e.hit_disagreement, bounds.hit_disagreement);
  check("distance RMS", e.distance_rms, bounds.distance_rms);
  check("image RMS", e.image_rms, bounds.image_rms);
  if (exceeded.str().empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "exceeds its stated bounds:" << exceeded.str();
}

}  // namespace vf::test
