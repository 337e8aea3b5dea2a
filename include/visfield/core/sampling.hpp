#pragma once
/// \file Warps from the unit square to directions (see shared design/sampling.md §3).

#include <cmath>
#include <numbers>

#include "visfield/core/vec.hpp"

namespace vf {

/// Shirley–Chiu concentric map from [0,1)^2 to the unit disk (area preserving).
inline void concentric_disk(float s, float t, float& x, float& y) {
  const float a = 2.0f * s - 1.0f, b = 2.0f * t - 1.0f;
  if (a == 0.0f && b == 0.0f) { x = y = 0.0f; return; }
  float r, phi;
  if (std::fabs(a) >= std::fabs(b)) { r = a; phi = (std::numbers::pi_v<float> / 4.0f) * (b / a); }
  else { r = b; phi = std::numbers::pi_v<float> / 2.0f - (std::numbers::pi_v<float> / 4.0f) * (a / b); }
  x = r * std::cos(phi);
  y = r * std::sin(phi);
}

/// Cosine-weighted direction on the +z hemisphere (concentric map + Malley lift); pdf = cos/pi.
inline Vec3f cosine_hemisphere(float s, float t) {
  float x, y;
  concentric_disk(s, t, x, y);
  return {x, y, std::sqrt(std::fmax(0.0f, 1.0f - x * x - y * y))};
}

/// Uniform direction on the unit sphere.
inline Vec3f uniform_sphere(float s, float t) {
  const float z = 1.0f - 2.0f * s;
  const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
  const float phi = 2.0f * std::numbers::pi_v<float> * t;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace vf
