#pragma once
// Private to accel (BeamField): the depth range of a triangle inside one beam. The paper clips each
// triangle to the tile's boundary before comparing its depth range with the tile-BSP's planes, so
// that a large triangle crossing many beams is only referenced by the leaves it really reaches there.

#include <algorithm>
#include <cmath>

#include "beam_field/tile_geometry.hpp"

namespace vf::beam {

/// Depth interval [lo, hi].
struct DepthRange {
  double lo, hi;
};

/// The depth range of triangle (a, b, c) (PSF coordinates) within the beam over the square
/// [s0, s1] × [t0, t1]: Sutherland–Hodgman clipping of the projected triangle, depth interpolated
/// along the edges; the extreme depths of a convex polygon lie at its corners. A triangle seen
/// edge-on (projected area below `flat_area`) or one whose clip comes out empty by rounding keeps
/// its whole depth range (conservative). O(1).
inline DepthRange clipped_depth_range(const PsfPoint& a, const PsfPoint& b, const PsfPoint& c, double s0, double s1,
                                      double t0, double t1, double flat_area) {
  const DepthRange whole{std::min({a.w, b.w, c.w}), std::max({a.w, b.w, c.w})};
  const double area2 = (b.s - a.s) * (c.t - a.t) - (b.t - a.t) * (c.s - a.s);
  if (std::fabs(area2) <= flat_area) return whole;
  PsfPoint poly[2][9] = {{a, b, c}};
  int count = 3, cur = 0;
  // Half-planes s >= s0, s <= s1, t >= t0, t <= t1 as (axis, bound, sign): inside when sign·(x - bound) >= 0.
  const struct {
    bool t_axis;
    double bound, sign;
  } planes[4] = {{false, s0, 1.0}, {false, s1, -1.0}, {true, t0, 1.0}, {true, t1, -1.0}};
  for (const auto& plane : planes) {
    const PsfPoint* in = poly[cur];
    PsfPoint* out = poly[1 - cur];
    int out_count = 0;
    for (int i = 0; i < count; ++i) {
      const PsfPoint& p = in[i];
      const PsfPoint& q = in[(i + 1) % count];
      const double dp = plane.sign * ((plane.t_axis ? p.t : p.s) - plane.bound);
      const double dq = plane.sign * ((plane.t_axis ? q.t : q.s) - plane.bound);
      if (dp >= 0.0) out[out_count++] = p;
      if ((dp >= 0.0) != (dq >= 0.0)) {
        const double f = dp / (dp - dq);
        out[out_count++] = {p.s + f * (q.s - p.s), p.t + f * (q.t - p.t), p.w + f * (q.w - p.w)};
      }
    }
    count = out_count;
    cur = 1 - cur;
    if (count == 0) return whole;
  }
  DepthRange r{poly[cur][0].w, poly[cur][0].w};
  for (int i = 1; i < count; ++i) r.lo = std::min(r.lo, poly[cur][i].w), r.hi = std::max(r.hi, poly[cur][i].w);
  return r;
}

}  // namespace vf::beam
