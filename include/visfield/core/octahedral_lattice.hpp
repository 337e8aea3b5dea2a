#pragma once
/// \file The octahedral lattice behind both sampled sets of directions: BeamField's lines and the
/// ObjectField's positional samples (host and device, no STL). Lattice points (i, j) with
/// |i| + |j| <= n (n = 2^level) lie on the four upper faces of the octahedron; the equal-area
/// diamond map takes them to the upper unit hemisphere:
///   u = i/n, v = j/n, r = |u| + |v|, φ = (π/2)|v|/r,
///   ω = (sgn u cos φ · r√(2 − r²), sgn v sin φ · r√(2 − r²), 1 − r²).
/// Its inverse gives a direction's continuous lattice coordinates; the lattice triangle holding
/// them has the direction's nearest lattice point among its corners (checked against brute force
/// in the tests), and its barycentric weights blend values stored at the corners.

#include "visfield/core/host_device.hpp"

namespace vf::octa {

/// Number of lattice points of half-width n: 2n² + 2n + 1 (545 at n = 16).
VF_HOST_DEVICE inline long long point_count(int n) { return 2LL * n * n + 2LL * n + 1; }

/// Dense index of (i, j), |i| + |j| <= n, over [0, point_count(n)): rows of constant i, in order.
VF_HOST_DEVICE inline long long point_index(int i, int j, int n) {
  const int ai = i < 0 ? -i : i;
  const long long row_start = i <= 0 ? static_cast<long long>(i + n) * (i + n)
                                     : static_cast<long long>(n) * n + static_cast<long long>(2 * n + 2) * i -
                                           static_cast<long long>(i) * i;
  return row_start + j + n - ai;
}

/// The unit direction of lattice point (i, j) (z >= 0). Exact zeros where i or j is zero and on
/// the equator (|i| + |j| = n), so that points mirrored across an axis mirror bit for bit. In float
/// the angle's sine and cosine are hd::quadrant_sincos's polynomials, so that SIMD lanes compute
/// the same directions without a table.
template <class Real>
VF_HOST_DEVICE inline hd::Vec3<Real> point_direction(int i, int j, int n) {
  const Real u = static_cast<Real>(i) / n, v = static_cast<Real>(j) / n;
  const Real r = hd::abs(u) + hd::abs(v);
  if (r == Real(0)) return {Real(0), Real(0), Real(1)};
  const Real phi = (hd::kPi<Real> / 2) * hd::abs(v) / r;
  const Real radial = r * hd::sqrt(Real(2) - r * r);
  Real sin_phi, cos_phi;
  hd::quadrant_sincos(phi, sin_phi, cos_phi);
  const Real x = i == 0 ? Real(0) : hd::copysign(cos_phi * radial, u);
  const Real y = j == 0 ? Real(0) : hd::copysign(sin_phi * radial, v);
  const bool equator = (i < 0 ? -i : i) + (j < 0 ? -j : j) == n;
  return {x, y, equator ? Real(0) : Real(1) - r * r};
}

/// Continuous lattice coordinates (a, b) of unit direction `d` with d.z >= 0: the inverse of
/// point_direction, so that |a| + |b| <= n. In float the angle is hd::lookup_atan2's polynomial.
template <class Real>
VF_HOST_DEVICE inline void coordinates(const hd::Vec3<Real>& d, int n, Real& a, Real& b) {
  const Real r = hd::sqrt(hd::max(Real(0), Real(1) - d.z));
  const Real phi = hd::lookup_atan2(hd::abs(d.y), hd::abs(d.x));
  // A product by the constant 2/π, not a division by π/2: lookups run on lanes whose divider is
  // their busiest unit (docs/objectfield-measurements.md).
  const Real v = r * phi * (2 / hd::kPi<Real>), u = r - v;
  a = d.x > 0 ? n * u : (d.x < 0 ? -n * u : Real(0));
  b = d.y > 0 ? n * v : (d.y < 0 ? -n * v : Real(0));
}

/// One lattice triangle: its corners and the barycentric weights of the point it was found for.
/// A corner beyond the rim (|i| + |j| > n, possible only for points on the rim) has weight 0.
template <class Real>
struct Triangle {
  int i[3], j[3];
  Real weight[3];
};

/// The lattice triangle containing coordinates (a, b). The lattice's diagonals run i + j = c in
/// quadrants I and III and i − j = c in II and IV (the octahedron's face subdivision).
template <class Real>
VF_HOST_DEVICE inline Triangle<Real> containing_triangle(Real a, Real b, int n) {
  const int i0 = hd::clamp(static_cast<int>(hd::floor(a)), -n, n - 1);
  const int j0 = hd::clamp(static_cast<int>(hd::floor(b)), -n, n - 1);
  const Real f = a - i0, g = b - j0;
  Triangle<Real> t;
  if ((i0 >= 0) == (j0 >= 0)) {
    if (f + g <= Real(1))
      t = {{i0, i0 + 1, i0}, {j0, j0, j0 + 1}, {Real(1) - f - g, f, g}};
    else
      t = {{i0 + 1, i0 + 1, i0}, {j0 + 1, j0, j0 + 1}, {f + g - Real(1), Real(1) - g, Real(1) - f}};
  } else {
    if (g <= f)
      t = {{i0, i0 + 1, i0 + 1}, {j0, j0, j0 + 1}, {Real(1) - f, f - g, g}};
    else
      t = {{i0, i0, i0 + 1}, {j0, j0 + 1, j0 + 1}, {Real(1) - g, g - f, f}};
  }
  for (int k = 0; k < 3; ++k) {
    const int ai = t.i[k] < 0 ? -t.i[k] : t.i[k], aj = t.j[k] < 0 ? -t.j[k] : t.j[k];
    if (ai + aj > n) t.weight[k] = Real(0);
  }
  return t;
}

}  // namespace vf::octa
