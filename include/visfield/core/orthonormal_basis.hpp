#pragma once
/// \file The branchless orthonormal basis around a unit vector (Duff et al., "Building an
/// Orthonormal Basis, Revisited", JCGT 2017); host and device, no STL. For w.z >= 0 it is the
/// minimal rotation taking +z to w applied to +x and +y, so it is the identity at w = +z and smooth
/// over the closed upper hemisphere; below, it is the mirrored construction (smooth except at the
/// equator's seam between the two).

#include "visfield/core/host_device.hpp"

namespace vf {

/// Unit vectors u, v with (u, v, w) orthonormal and u × v = w, for unit `w`. Exact to rounding.
template <class Real>
struct OrthonormalBasis {
  hd::Vec3<Real> u, v, w;
};

/// sign(w.z) + w.z, +0 counting as positive: what orthonormal_basis(w) divides by (magnitude in [1, 2]).
template <class Real>
VF_HOST_DEVICE inline Real basis_denominator(const hd::Vec3<Real>& w) {
  return hd::copysign(Real(1), w.z) + w.z;
}

/// orthonormal_basis(w) given `inverse` = 1 / basis_denominator(w), for a caller that gets the
/// reciprocal from a division it shares (hd::reciprocals); the same bits when it is the quotient.
template <class Real>
VF_HOST_DEVICE inline OrthonormalBasis<Real> orthonormal_basis(const hd::Vec3<Real>& w, Real inverse) {
  const Real sign = hd::copysign(Real(1), w.z);
  const Real a = -inverse;
  const Real b = w.x * w.y * a;
  return {{Real(1) + sign * w.x * w.x * a, sign * b, -sign * w.x}, {b, sign + w.y * w.y * a, -w.y}, w};
}

/// The basis around unit `w` (the sign of w.z picks the construction; +0 counts as upper).
template <class Real>
VF_HOST_DEVICE inline OrthonormalBasis<Real> orthonormal_basis(const hd::Vec3<Real>& w) {
  return orthonormal_basis(w, Real(1) / basis_denominator(w));
}

}  // namespace vf
