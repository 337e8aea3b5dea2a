#pragma once
/// \file Perfect splits: the bounds of the part of a triangle inside an axis-aligned box
/// (Sutherland–Hodgman clipping of the triangle against the box's six planes).

#include <array>

#include "visfield/core/bounds.hpp"

namespace vf::kd {

/// Bounds of (triangle ∩ box), conservative: they contain every point of the exact intersection
/// and lie inside `box`. Clipping runs in double precision; coordinates produced by interpolation
/// are rounded outwards to float (at most one float ulp beyond the exact value), while corner
/// coordinates and clip-plane coordinates are exact. Empty bounds when the triangle misses the box.
/// O(1): at most 9 polygon vertices.
Bounds3f clipped_triangle_bounds(const std::array<Vec3f, 3>& triangle, const Bounds3f& box);

/// The box [a.lo, a.hi] ∩ [b.lo, b.hi] (empty when they are disjoint).
inline Bounds3f intersect_bounds(const Bounds3f& a, const Bounds3f& b) {
  Bounds3f r;
  r.lo = max(a.lo, b.lo);
  r.hi = min(a.hi, b.hi);
  return r.empty() ? Bounds3f{} : r;
}

}  // namespace vf::kd
