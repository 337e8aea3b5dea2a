#pragma once
/// \file The ObjectField's positional samples on its bounding sphere, looked up in O(1); host and
/// device, no STL. The set is two octahedral lattices of half-width n (see octahedral_lattice.hpp):
/// the upper hemisphere's points, then the same points mirrored to z < 0, the equator ring stored
/// in both — 2(2n² + 2n + 1) samples: 290, 1090, 4226, 16642 at levels 3–6. A caller keeps the
/// upper hemisphere's point_count(n) unit directions in a table (index = octa::point_index); the
/// lower sample of lattice point (i, j) has index point_count(n) + point_index(i, j, n).

#include "visfield/core/octahedral_lattice.hpp"

namespace vf::field {

/// Number of positional samples of half-width n: 2(2n² + 2n + 1).
VF_HOST_DEVICE inline long long position_count(int n) { return 2 * octa::point_count(n); }

/// The three positional samples around a direction and their blending weights (sum 1; a sample
/// beyond the lattice rim has weight 0 and repeats a valid index).
template <class Real>
struct PositionBlend {
  int index[3];
  Real weight[3];
};

namespace detail {
/// Canonical upper direction of `d` and the index offset of its hemisphere (z >= 0: upper).
template <class Real>
VF_HOST_DEVICE inline hd::Vec3<Real> fold_to_upper(const hd::Vec3<Real>& d, int n, int& offset) {
  offset = d.z >= 0 ? 0 : static_cast<int>(octa::point_count(n));
  return {d.x, d.y, hd::abs(d.z)};
}
}  // namespace detail

/// Index of the positional sample nearest to unit direction `d` (from the sphere's centre): the
/// corner of d's lattice triangle with the largest cosine to d. `upper` holds the upper
/// hemisphere's sample directions. Exact: equal to the brute-force argmax (tested). O(1).
template <class Real>
VF_HOST_DEVICE inline int nearest_position(const hd::Vec3<Real>& d, int n, const hd::Vec3<Real>* upper) {
  int offset;
  const hd::Vec3<Real> e = detail::fold_to_upper(d, n, offset);
  Real a, b;
  octa::coordinates(e, n, a, b);
  const octa::Triangle<Real> t = octa::containing_triangle(a, b, n);
  int best = -1;
  Real best_cos = Real(-2);
  for (int k = 0; k < 3; ++k) {
    const int ai = t.i[k] < 0 ? -t.i[k] : t.i[k], aj = t.j[k] < 0 ? -t.j[k] : t.j[k];
    if (ai + aj > n) continue;
    const int index = static_cast<int>(octa::point_index(t.i[k], t.j[k], n));
    const Real c = hd::fused_dot(e, upper[index]);
    if (c > best_cos) {
      best_cos = c;
      best = index;
    }
  }
  return best + offset;
}

/// Index of the corner of d's lattice triangle with the largest barycentric weight (the first of
/// equals; corners beyond the rim left out): the lookups' sample. It needs no sample direction, where
/// nearest_position() compares the three corners' cosines; it picks another sample for ~7.5% of
/// directions, at most ~18% farther in angle (tests/unit/field/test_position_lookup.cpp), which
/// leaves the fields' error level and takes two of the three table reads out of a SIMD lookup
/// (docs/objectfield-measurements.md). O(1).
template <class Real>
VF_HOST_DEVICE inline int heaviest_corner_position(const hd::Vec3<Real>& d, int n) {
  int offset;
  const hd::Vec3<Real> e = detail::fold_to_upper(d, n, offset);
  Real a, b;
  octa::coordinates(e, n, a, b);
  const octa::Triangle<Real> t = octa::containing_triangle(a, b, n);
  int best = 0;
  Real best_weight = Real(-2);
  for (int k = 0; k < 3; ++k) {
    const int ai = t.i[k] < 0 ? -t.i[k] : t.i[k], aj = t.j[k] < 0 ? -t.j[k] : t.j[k];
    if (ai + aj > n || !(t.weight[k] > best_weight)) continue;
    best_weight = t.weight[k];
    best = k;
  }
  return static_cast<int>(octa::point_index(t.i[best], t.j[best], n)) + offset;
}

/// The corners of d's lattice triangle with barycentric weights in lattice coordinates: blending
/// the values stored at them is continuous across triangle edges (and across the equator, whose
/// ring both hemispheres share). O(1).
template <class Real>
VF_HOST_DEVICE inline PositionBlend<Real> blend_positions(const hd::Vec3<Real>& d, int n) {
  int offset;
  const hd::Vec3<Real> e = detail::fold_to_upper(d, n, offset);
  Real a, b;
  octa::coordinates(e, n, a, b);
  const octa::Triangle<Real> t = octa::containing_triangle(a, b, n);
  PositionBlend<Real> blend;
  Real total = 0;
  int valid = -1;
  for (int k = 0; k < 3; ++k) {
    const int ai = t.i[k] < 0 ? -t.i[k] : t.i[k], aj = t.j[k] < 0 ? -t.j[k] : t.j[k];
    blend.weight[k] = hd::max(Real(0), t.weight[k]);
    blend.index[k] = ai + aj > n ? -1 : static_cast<int>(octa::point_index(t.i[k], t.j[k], n)) + offset;
    if (blend.index[k] < 0) blend.weight[k] = 0;
    if (blend.index[k] >= 0 && (valid < 0 || blend.weight[k] > blend.weight[valid])) valid = k;
    total += blend.weight[k];
  }
  for (int k = 0; k < 3; ++k) {
    if (blend.index[k] < 0) blend.index[k] = blend.index[valid];
    blend.weight[k] = total > 0 ? blend.weight[k] / total : (k == valid ? Real(1) : Real(0));
  }
  return blend;
}

}  // namespace vf::field
