#pragma once
/// \file Warps from the unit square to directions (see shared design/sampling.md §3), host and
/// device: the CPU renderers and the GPU kernels (gpu/ray_generation.hpp) draw their directions
/// with these very functions. Sines and cosines are the lookups' polynomials (hd::quadrant_sincos),
/// not libm's: inline, the same bits on every CPU and GPU, within 1e-6 of the true values.

#include "visfield/core/host_device.hpp"
#include "visfield/core/vec.hpp"

namespace vf {

/// sin and cos of `phi` in [−π/4, π/4] by the lookups' polynomials (odd sine, even cosine).
VF_HOST_DEVICE inline void sincos_eighth(float phi, float& s, float& c) {
  hd::quadrant_sincos(hd::abs(phi), s, c);
  s = hd::copysign(s, phi);
}

/// sin and cos of 2πv for v in [0, 1): the quarter turn reduced to [0, π/2] (exactly: 4v and its
/// fraction are exact), then hd::quadrant_sincos and the quadrant's signs.
VF_HOST_DEVICE inline void sincos_turn(float v, float& s, float& c) {
  const float x = 4.0f * v;
  int q = static_cast<int>(hd::floor(x));
  q = q < 0 ? 0 : (q > 3 ? 3 : q);
  float sr, cr;
  hd::quadrant_sincos((x - static_cast<float>(q)) * (hd::kPi<float> / 2.0f), sr, cr);
  switch (q) {
    case 0: s = sr; c = cr; break;
    case 1: s = cr; c = -sr; break;
    case 2: s = -sr; c = -cr; break;
    default: s = -cr; c = sr; break;
  }
}

/// Shirley–Chiu concentric map from [0,1)² to the unit disk (area preserving); the second branch's
/// angle π/2 − ψ is taken as the swap of ψ's sine and cosine.
VF_HOST_DEVICE inline void concentric_disk(float s, float t, float& x, float& y) {
  const float a = 2.0f * s - 1.0f, b = 2.0f * t - 1.0f;
  if (a == 0.0f && b == 0.0f) {
    x = y = 0.0f;
    return;
  }
  float sn, cs;
  if (hd::abs(a) >= hd::abs(b)) {
    sincos_eighth((hd::kPi<float> / 4.0f) * (b / a), sn, cs);
    x = a * cs;
    y = a * sn;
  } else {
    sincos_eighth((hd::kPi<float> / 4.0f) * (a / b), sn, cs);
    x = b * sn;
    y = b * cs;
  }
}

/// Cosine-weighted direction on the +z hemisphere (concentric map + Malley lift); pdf = cos/π.
VF_HOST_DEVICE inline Vec3f cosine_hemisphere(float s, float t) {
  float x, y;
  concentric_disk(s, t, x, y);
  return {x, y, hd::sqrt(hd::max(0.0f, 1.0f - x * x - y * y))};
}

/// Uniform direction on the unit sphere.
VF_HOST_DEVICE inline Vec3f uniform_sphere(float s, float t) {
  const float z = 1.0f - 2.0f * s;
  const float r = hd::sqrt(hd::max(0.0f, 1.0f - z * z));
  float sn, cs;
  sincos_turn(t, sn, cs);
  return {r * cs, r * sn, z};
}

}  // namespace vf
