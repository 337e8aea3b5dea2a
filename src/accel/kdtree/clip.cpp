#include "kdtree/clip.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vf::kd {
namespace {

// Interpolated coordinates are off by a few double ulps of the largest magnitude involved; this
// margin (relative to that magnitude) is far larger, and far below a float ulp.
constexpr double kInterpolationMargin = 0x1p-40;

struct ClipVertex {
  double p[3];
  unsigned exact;  // bit a: p[a] is exact (a corner or clip-plane coordinate)
};

struct Polygon {
  ClipVertex v[9];  // a triangle gains at most one vertex per clip plane
  int size = 0;
};

/// Keeps the part of `in` with p[axis] <= s (keep_below) or >= s; new vertices lie exactly on s.
void clip_polygon(const Polygon& in, int axis, double s, bool keep_below, Polygon& out) {
  out.size = 0;
  const auto inside = [&](const ClipVertex& v) { return keep_below ? v.p[axis] <= s : v.p[axis] >= s; };
  const auto crossing = [&](const ClipVertex& a, const ClipVertex& b) {
    const double t = (s - a.p[axis]) / (b.p[axis] - a.p[axis]);
    if (t == 0.0) return a;  // a lies in the plane
    ClipVertex x{};
    x.exact = 1u << axis;
    for (int k = 0; k < 3; ++k) {
      if (k == axis) {
        x.p[k] = s;
      } else if (a.p[k] == b.p[k]) {
        x.p[k] = a.p[k];
        x.exact |= a.exact & b.exact & (1u << k);
      } else {
        x.p[k] = a.p[k] + t * (b.p[k] - a.p[k]);
      }
    }
    return x;
  };
  for (int i = 0; i < in.size; ++i) {
    const ClipVertex& prev = in.v[(i + in.size - 1) % in.size];
    const ClipVertex& cur = in.v[i];
    const bool cur_in = inside(cur), prev_in = inside(prev);
    if (cur_in != prev_in) out.v[out.size++] = crossing(prev_in ? prev : cur, prev_in ? cur : prev);
    if (cur_in) out.v[out.size++] = cur;
  }
}

/// Largest float <= x.
float round_down(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

/// Smallest float >= x.
float round_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace

Bounds3f clipped_triangle_bounds(const std::array<Vec3f, 3>& triangle, const Bounds3f& box) {
  Polygon a, b;
  a.size = 3;
  double scale[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    a.v[i].exact = 7u;
    for (int k = 0; k < 3; ++k) {
      a.v[i].p[k] = triangle[i][k];
      scale[k] = std::max(scale[k], std::fabs(static_cast<double>(triangle[i][k])));
    }
  }
  for (int k = 0; k < 3; ++k)
    scale[k] = std::max({scale[k], std::fabs(static_cast<double>(box.lo[k])), std::fabs(static_cast<double>(box.hi[k]))});

  Polygon* cur = &a;
  Polygon* next = &b;
  for (int axis = 0; axis < 3; ++axis) {
    for (const bool keep_below : {false, true}) {
      const double s = keep_below ? box.hi[axis] : box.lo[axis];
      bool all_inside = true;
      for (int i = 0; i < cur->size && all_inside; ++i)
        all_inside = keep_below ? cur->v[i].p[axis] <= s : cur->v[i].p[axis] >= s;
      if (all_inside) continue;
      clip_polygon(*cur, axis, s, keep_below, *next);
      std::swap(cur, next);
      if (cur->size == 0) return {};
    }
  }

  Bounds3f result;
  for (int i = 0; i < cur->size; ++i) {
    const ClipVertex& v = cur->v[i];
    for (int k = 0; k < 3; ++k) {
      const bool exact = (v.exact >> k) & 1u;
      const double margin = exact ? 0.0 : kInterpolationMargin * scale[k];
      result.lo[k] = std::min(result.lo[k], exact ? static_cast<float>(v.p[k]) : round_down(v.p[k] - margin));
      result.hi[k] = std::max(result.hi[k], exact ? static_cast<float>(v.p[k]) : round_up(v.p[k] + margin));
    }
  }
  // Rounding outwards may step past the box; the exact intersection lies inside it.
  result.lo = max(result.lo, box.lo);
  result.hi = min(result.hi, box.hi);
  return result;
}

}  // namespace vf::kd
