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

/// The basis around unit `w` (the sign of w.z picks the construction; +0 counts as upper).
template <class Real>
VF_HOST_DEVICE inline OrthonormalBasis<Real> orthonormal_basis(const hd::Vec3<Real>& w) {
  const Real sign = hd::copysign(Real(1), w.z);
  const Real a = Real(-1) / (sign + w.z);
  const Real b = w.x * w.y * a;
  return {{Real(1) + sign * w.x * w.x * a, sign * b, -sign * w.x}, {b, sign + w.y * w.y * a, -w.y}, w};
}

}  // namespace vf
