#include "agreement.hpp"

#include <algorithm>
#include <cmath>

namespace vf::bench {

bool same_closest_hit(const Hit& a, const Hit& b) {
  const bool a_hit = a.found, b_hit = b.found;
  if (a_hit != b_hit) return false;
  if (!a_hit) return true;
  const float tolerance = std::max(kRelativeTTolerance * std::max(std::fabs(a.t), std::fabs(b.t)), kAbsoluteTTolerance);
  return std::fabs(a.t - b.t) <= tolerance;
}

std::size_t count_hit_mismatches(std::span<const Hit> a, std::span<const Hit> b) {
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < a.size(); ++i) mismatches += same_closest_hit(a[i], b[i]) ? 0 : 1;
  return mismatches;
}

std::size_t count_occlusion_mismatches(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < a.size(); ++i) mismatches += (a[i] != 0) != (b[i] != 0) ? 1 : 0;
  return mismatches;
}

std::size_t count_mismatches(const QueryResults& a, const QueryResults& b, RayKind kind) {
  return is_occlusion_kind(kind) ? count_occlusion_mismatches(a.occluded, b.occluded)
                                 : count_hit_mismatches(a.hits, b.hits);
}

ApproximateAgreement measure_agreement(const QueryResults& approximate, const QueryResults& exact, RayKind kind,
                                       std::span<const Ray> rays) {
  ApproximateAgreement agreement;
  const double n = static_cast<double>(std::max<std::size_t>(rays.size(), 1));
  if (is_occlusion_kind(kind)) {
    agreement.differing_fraction = static_cast<double>(count_occlusion_mismatches(approximate.occluded, exact.occluded)) / n;
    return agreement;
  }
  std::size_t differing = 0, both = 0;
  double error_sum = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit& a = approximate.hits[i];
    const Hit& e = exact.hits[i];
    if (a.found != e.found) {
      ++differing;
    } else if (a.found) {
      ++both;
      error_sum += std::fabs(static_cast<double>(a.t) - e.t) * length(rays[i].dir);
    }
  }
  agreement.differing_fraction = static_cast<double>(differing) / n;
  agreement.mean_distance_error = both > 0 ? error_sum / static_cast<double>(both) : 0.0;
  return agreement;
}

}  // namespace vf::bench
