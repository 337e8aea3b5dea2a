#pragma once
// Private to accel (BeamField): the part of a triangle inside one beam. The paper clips each triangle
// to the tile's boundary before comparing its depth range with the tile-BSP's planes, so that a large
// triangle crossing many beams is only referenced by the leaves it really reaches there; the clipped
// polygon's (s, t) box is the reference's footprint (tile_footprint.hpp).

#include <algorithm>
#include <cmath>

#include "beam_field/tile_geometry.hpp"

namespace vf::beam {

/// The PSF box [s_lo, s_hi] × [t_lo, t_hi] × [lo, hi] of (part of) a triangle; lo, hi is its depth range.
struct BeamBox {
  double lo, hi;
  double s_lo, s_hi, t_lo, t_hi;
};

/// The box of triangle (a, b, c) (PSF coordinates), whole.
inline BeamBox whole_box(const PsfPoint& a, const PsfPoint& b, const PsfPoint& c) {
  return {std::min({a.w, b.w, c.w}), std::max({a.w, b.w, c.w}), std::min({a.s, b.s, c.s}), std::max({a.s, b.s, c.s}),
          std::min({a.t, b.t, c.t}), std::max({a.t, b.t, c.t})};
}

/// The box of the part of triangle (a, b, c) (PSF coordinates) within the beam over the square
/// [s0, s1] × [t0, t1]: Sutherland–Hodgman clipping of the projected triangle, depth interpolated
/// along the edges; the extremes of a convex polygon lie at its corners. A triangle seen edge-on
/// (projected area below `flat_area`) or one whose clip comes out empty by rounding keeps its whole
/// box (conservative). O(1).
inline BeamBox clip_to_beam(const PsfPoint& a, const PsfPoint& b, const PsfPoint& c, double s0, double s1, double t0,
                            double t1, double flat_area) {
  const BeamBox whole = whole_box(a, b, c);
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
  const PsfPoint& first = poly[cur][0];
  BeamBox r{first.w, first.w, first.s, first.s, first.t, first.t};
  for (int i = 1; i < count; ++i) {
    const PsfPoint& q = poly[cur][i];
    r.lo = std::min(r.lo, q.w), r.hi = std::max(r.hi, q.w);
    r.s_lo = std::min(r.s_lo, q.s), r.s_hi = std::max(r.s_hi, q.s);
    r.t_lo = std::min(r.t_lo, q.t), r.t_hi = std::max(r.t_hi, q.t);
  }
  return r;
}

}  // namespace vf::beam
