#pragma once
/// \file Axis-aligned bounding boxes.

#include <limits>

#include "visfield/core/vec.hpp"

namespace vf {

/// Axis-aligned box [lo, hi]; default-constructed it is empty (lo = +inf, hi = -inf).
struct Bounds3f {
  Vec3f lo{std::numeric_limits<float>::infinity()};
  Vec3f hi{-std::numeric_limits<float>::infinity()};

  /// Grows the box to contain point p.
  constexpr void extend(const Vec3f& p) { lo = min(lo, p); hi = max(hi, p); }
  /// Grows the box to contain box b.
  constexpr void extend(const Bounds3f& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
  /// True when the box contains no point.
  constexpr bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  /// hi - lo (meaningless when empty).
  constexpr Vec3f extent() const { return hi - lo; }
  /// Box centre.
  constexpr Vec3f center() const { return (lo + hi) * 0.5f; }
  /// Half the surface area (the SAH only needs ratios).
  constexpr float half_area() const {
    if (empty()) return 0.0f;
    const Vec3f e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  /// True when p lies inside or on the box.
  constexpr bool contains(const Vec3f& p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
};

}  // namespace vf
