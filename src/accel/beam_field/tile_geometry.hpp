#pragma once
// Private to accel (BeamField): the arithmetic that build and query must share bit for bit: PSF
// projection, tile cells, and the leaf of a depth.

#include <algorithm>
#include <array>

#include "beam_field/beam_layout.hpp"

namespace vf::beam {

/// A point in PSF coordinates: beam position (s, t) and depth w along the line.
struct PsfPoint {
  double s, t, w;
};

/// PSF coordinates of float point p relative to the sphere centre (p - c is exact in double).
inline PsfPoint project(const FrameD& f, const std::array<double, 3>& c, const Vec3f& p) {
  const double x = static_cast<double>(p.x) - c[0], y = static_cast<double>(p.y) - c[1], z = static_cast<double>(p.z) - c[2];
  return {f.u[0] * x + f.u[1] * y + f.u[2] * z, f.v[0] * x + f.v[1] * y + f.v[2] * z, f.w[0] * x + f.w[1] * y + f.w[2] * z};
}

inline int TileGeometry::cell(double s) const {
  const double x = (s + radius) * inv_tile_size;
  if (!(x > 0.0)) return 0;
  if (x >= n - 1) return n - 1;
  return static_cast<int>(x);
}

/// Leaf of depth w in a record with start `lo`, `scale` leaves per unit depth and leaves 0..last:
/// floor((w - lo) * scale) clamped. Monotonic in w, which is all that build and query rely on.
inline int leaf_of(double w, double lo, double scale, int last) {
  const double x = (w - lo) * scale;
  if (!(x > 0.0)) return 0;
  if (x >= last) return last;
  return static_cast<int>(x);
}

}  // namespace vf::beam
