#pragma once
/// \file What the update tests compare: probe rays around a scene and the count of rays on which two
/// structures answer differently, for any updatable structure.

#include <cstdint>
#include <vector>

#include "differential/ray_sets.hpp"
#include "support/same_hit.hpp"

namespace vf::test {

/// Random rays around `set` and AO-like rays from its surfaces, `per_kind` of each.
inline std::vector<Ray> probe_rays(const TriangleSet& set, std::uint64_t seed, std::size_t per_kind) {
  std::vector<Ray> rays = random_rays(set, seed, per_kind);
  const std::vector<Ray> surface = model_rays(set, seed + 1, per_kind);
  rays.insert(rays.end(), surface.begin(), surface.end());
  return rays;
}

/// Number of rays on which `a` and `b` differ (closest hit bit for bit, or occlusion).
template <class A, class B>
std::size_t differences(const A& a, const B& b, const std::vector<Ray>& rays) {
  std::size_t n = 0;
  for (const Ray& ray : rays) n += same_bits(a.intersect(ray), b.intersect(ray)) && a.occluded(ray) == b.occluded(ray) ? 0 : 1;
  return n;
}

}  // namespace vf::test
