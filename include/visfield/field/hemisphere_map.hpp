#pragma once
/// \file The square ↔ hemisphere maps of an ObjectField's direction tables (displacement-field
/// paper, "Sampling a Hemisphere of Directions", Figure 3); host and device, no STL. A table is
/// N×N cells over the unit square (s, t) ∈ [0, 1)²; cell (i, j) spans [i/N, (i+1)/N) × [j/N, (j+1)/N)
/// and stands for the direction of its centre. Directions are in the local frame of the hemisphere
/// (its pole is +z).
///
///  - polar: φ = 2πs, θ = (π/2)t (equal angles; cells crowd at the pole, as the paper's Figure 3a).
///  - rejection_malley: (x, y) = (2s − 1, 2t − 1) lifted by Malley, ω = (x, y, √(1 − x² − y²));
///    cells that miss the disk are unused (about 21.5%).
///  - concentric_malley: Shirley–Chiu concentric map to the disk, then Malley: every cell has the
///    same projected solid angle π/N² (the paper's choice, and our default).
///  - concentric_equal_area: the concentric map, then the equal-area lift
///    ω = (x√(2 − ρ²), y√(2 − ρ²), 1 − ρ²): every cell has solid angle 2π/N².

#include "visfield/core/host_device.hpp"

namespace vf::field {

/// How a direction table's cells are laid over the hemisphere. The values are stored in field files.
enum class HemisphereMapping : unsigned char {
  polar = 0,
  rejection_malley = 1,
  concentric_malley = 2,
  concentric_equal_area = 3,
};

/// Number of mappings (they are numbered 0 .. kMappingCount − 1).
inline constexpr int kMappingCount = 4;

/// Shirley–Chiu concentric map: (s, t) in [0, 1]² to the unit disk, area-preserving.
template <class Real>
VF_HOST_DEVICE inline void concentric_to_disk(Real s, Real t, Real& x, Real& y) {
  const Real a = 2 * s - 1, b = 2 * t - 1;
  if (a == Real(0) && b == Real(0)) {
    x = y = Real(0);
    return;
  }
  Real r, phi;
  if (hd::abs(a) >= hd::abs(b)) {
    r = a;
    phi = (hd::kPi<Real> / 4) * (b / a);
  } else {
    r = b;
    phi = hd::kPi<Real> / 2 - (hd::kPi<Real> / 4) * (a / b);
  }
  x = r * hd::cos(phi);
  y = r * hd::sin(phi);
}

/// Inverse of concentric_to_disk: a point of the closed unit disk to (s, t) in [0, 1]².
template <class Real>
VF_HOST_DEVICE inline void disk_to_concentric(Real x, Real y, Real& s, Real& t) {
  const Real r = hd::sqrt(hd::fma(x, x, y * y));
  Real a = 0, b = 0;
  if (r > Real(0)) {
    if (hd::abs(x) >= hd::abs(y)) {
      a = hd::copysign(r, x);
      b = a * (4 / hd::kPi<Real>) * hd::atan_unit(y / x);
    } else {
      b = hd::copysign(r, y);
      a = b * (4 / hd::kPi<Real>) * hd::atan_unit(x / y);
    }
  }
  // (a + 1)/2 rounded once: the same value as rounding a + 1 and halving exactly, in one operation.
  s = hd::fma(a, Real(0.5), Real(0.5));
  t = hd::fma(b, Real(0.5), Real(0.5));
}

/// The local direction of square point (s, t) under `mapping` (unit length). For
/// rejection_malley a point outside the disk is first pulled onto its rim.
template <class Real>
VF_HOST_DEVICE inline hd::Vec3<Real> square_to_direction(HemisphereMapping mapping, Real s, Real t) {
  switch (mapping) {
    case HemisphereMapping::polar: {
      const Real phi = 2 * hd::kPi<Real> * s, theta = (hd::kPi<Real> / 2) * t;
      const Real st = hd::sin(theta);
      return {st * hd::cos(phi), st * hd::sin(phi), hd::cos(theta)};
    }
    case HemisphereMapping::rejection_malley: {
      Real x = 2 * s - 1, y = 2 * t - 1;
      const Real rr = x * x + y * y;
      if (rr > Real(1)) {
        const Real k = 1 / hd::sqrt(rr);
        x *= k;
        y *= k;
      }
      return {x, y, hd::sqrt(hd::max(Real(0), 1 - x * x - y * y))};
    }
    case HemisphereMapping::concentric_malley: {
      Real x, y;
      concentric_to_disk(s, t, x, y);
      return {x, y, hd::sqrt(hd::max(Real(0), 1 - x * x - y * y))};
    }
    case HemisphereMapping::concentric_equal_area:
    default: {
      Real x, y;
      concentric_to_disk(s, t, x, y);
      const Real rr = x * x + y * y, k = hd::sqrt(hd::max(Real(0), 2 - rr));
      return {x * k, y * k, 1 - rr};
    }
  }
}

/// The square point (s, t) ∈ [0, 1]² of local unit direction `w` with w.z >= 0 (the inverse of
/// square_to_direction; for polar, s wraps into [0, 1)).
template <class Real>
VF_HOST_DEVICE inline void direction_to_square(HemisphereMapping mapping, const hd::Vec3<Real>& w, Real& s, Real& t) {
  switch (mapping) {
    case HemisphereMapping::polar: {
      Real phi = hd::lookup_atan2(w.y, w.x);
      if (phi < 0) phi += 2 * hd::kPi<Real>;
      s = phi / (2 * hd::kPi<Real>);
      if (s >= Real(1)) s = Real(0);
      t = hd::lookup_atan2(hd::sqrt(w.x * w.x + w.y * w.y), w.z) / (hd::kPi<Real> / 2);
      return;
    }
    case HemisphereMapping::rejection_malley:
      s = (w.x + 1) / 2;
      t = (w.y + 1) / 2;
      return;
    case HemisphereMapping::concentric_malley:
      disk_to_concentric(w.x, w.y, s, t);
      return;
    case HemisphereMapping::concentric_equal_area:
    default: {
      const Real k = 1 / hd::sqrt(1 + hd::max(Real(0), w.z));
      disk_to_concentric(w.x * k, w.y * k, s, t);
      return;
    }
  }
}

/// The cell index (0 .. N − 1) of square coordinate `s` in a table of N cells per side.
template <class Real>
VF_HOST_DEVICE inline int cell_of(Real s, int n) {
  const int i = static_cast<int>(s * n);
  return hd::clamp(i, 0, n - 1);
}

/// Whether cell (i, j) of an N×N table stands for directions under `mapping`: always, except for
/// rejection_malley cells that do not touch the unit disk.
template <class Real>
VF_HOST_DEVICE inline bool cell_used(HemisphereMapping mapping, int i, int j, int n) {
  if (mapping != HemisphereMapping::rejection_malley) return true;
  const Real half = Real(1) / n;
  const Real xc = 2 * (i + Real(0.5)) / n - 1, yc = 2 * (j + Real(0.5)) / n - 1;
  const Real dx = hd::max(Real(0), hd::abs(xc) - half), dy = hd::max(Real(0), hd::abs(yc) - half);
  return dx * dx + dy * dy < Real(1);
}

/// The direction a cell stands for: its centre's, except a used rejection_malley cell whose centre
/// lies outside the disk, which stands for the point where the segment from its point nearest the
/// origin to its centre crosses the rim.
template <class Real>
VF_HOST_DEVICE inline hd::Vec3<Real> cell_direction(HemisphereMapping mapping, int i, int j, int n) {
  const Real s = (i + Real(0.5)) / n, t = (j + Real(0.5)) / n;
  if (mapping == HemisphereMapping::rejection_malley) {
    const Real xc = 2 * s - 1, yc = 2 * t - 1;
    if (xc * xc + yc * yc > Real(1)) {
      const Real half = Real(1) / n;
      // Nearest point p of the cell to the origin, then p + λ(c − p) with |·| = 1.
      const Real px = hd::copysign(hd::max(Real(0), hd::abs(xc) - half), xc);
      const Real py = hd::copysign(hd::max(Real(0), hd::abs(yc) - half), yc);
      const Real ex = xc - px, ey = yc - py;
      const Real qa = ex * ex + ey * ey, qb = 2 * (px * ex + py * ey), qc = px * px + py * py - 1;
      const Real lambda = (-qb + hd::sqrt(hd::max(Real(0), qb * qb - 4 * qa * qc))) / (2 * qa);
      const Real x = px + lambda * ex, y = py + lambda * ey;
      return {x, y, hd::sqrt(hd::max(Real(0), 1 - x * x - y * y))};
    }
  }
  return square_to_direction(mapping, s, t);
}

}  // namespace vf::field
