#pragma once
/// \file The definition the exact structures must reproduce: intersect_triangle() on every triangle
/// in TriangleSet order, a strictly smaller t needed to replace a hit.

#include <bit>
#include <cstdint>
#include <optional>

#include "visfield/core/triangle_intersect.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

/// Closest hit by the scalar test over all triangles; ties go to the lowest index.
inline std::optional<Hit> scalar_closest(const TriangleSet& set, const Ray& ray) {
  const WatertightRay wr(ray);
  std::optional<Hit> best;
  for (std::size_t i = 0; i < set.size(); ++i) {
    TriangleHit h{};
    const float tmax = best ? best->t : ray.tmax;
    const auto& t = set.triangles[i];
    if (!intersect_triangle(wr, t[0], t[1], t[2], ray.tmin, tmax, h)) continue;
    if (best && !(h.t < best->t)) continue;
    best = Hit{h.t, h.u, h.v, set.prim[i], set.instance[i]};
  }
  return best;
}

/// True when the scalar test hits any triangle in [tmin, tmax].
inline bool scalar_occluded(const TriangleSet& set, const Ray& ray) {
  const WatertightRay wr(ray);
  for (const auto& t : set.triangles) {
    TriangleHit h{};
    if (intersect_triangle(wr, t[0], t[1], t[2], ray.tmin, ray.tmax, h)) return true;
  }
  return false;
}

/// Bitwise equality of two optional hits (t, u, v, prim, instance).
inline bool same_bits(const std::optional<Hit>& a, const std::optional<Hit>& b) {
  if (a.has_value() != b.has_value()) return false;
  if (!a) return true;
  const auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x); };
  return bits(a->t) == bits(b->t) && bits(a->u) == bits(b->u) && bits(a->v) == bits(b->v) && a->prim == b->prim &&
         a->instance == b->instance;
}

}  // namespace vf::test
