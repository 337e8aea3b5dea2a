#pragma once
/// \file Rules shared by the SAH kd-tree and median BSP builders: which child a triangle goes to
/// and the bounds of a triangle cut by a split plane.

#include <array>
#include <cstdint>

#include "kdtree/clip.hpp"

namespace vf::kd {

/// Which children of a split a triangle is referenced by.
enum class Side : std::uint8_t { below, above, both };

/// Side of a triangle whose bounds along the split axis are [lo, hi], for a plane at `p`. A triangle
/// touching the plane from one side goes to that side only; one lying in the plane (lo == hi == p)
/// goes below when `planar_below`, else above. Every point of the triangle then lies in the closed
/// box of a child that references it.
inline Side side_of(float lo, float hi, float p, bool planar_below) {
  if (lo == hi && lo == p) return planar_below ? Side::below : Side::above;
  if (hi <= p) return Side::below;
  if (lo >= p) return Side::above;
  return Side::both;
}

/// Bounds of a triangle that crosses a split plane, inside one child box: its clipped bounds
/// (perfect split), tightened by the bounds it had in the parent (`parent_bounds`, conservative);
/// when rounding makes those disjoint, parent_bounds ∩ child_box, so a reference is never lost.
inline Bounds3f straddler_bounds(const std::array<Vec3f, 3>& triangle, const Bounds3f& parent_bounds,
                                 const Bounds3f& child_box) {
  const Bounds3f clipped = intersect_bounds(clipped_triangle_bounds(triangle, child_box), parent_bounds);
  return clipped.empty() ? intersect_bounds(parent_bounds, child_box) : clipped;
}

}  // namespace vf::kd
