#pragma once
/// \file Rays and hits: the currency of every query.

#include <cstdint>
#include <limits>

#include "visfield/core/vec.hpp"

namespace vf {

/// Sentinel for "no primitive / no instance".
inline constexpr std::uint32_t kInvalidId = 0xffffffffu;

/// A ray segment org + t*dir for t in [tmin, tmax]; dir need not be unit length (t is in units of |dir|).
struct Ray {
  Vec3f org;
  Vec3f dir;
  float tmin = 0.0f;
  float tmax = std::numeric_limits<float>::infinity();
};

/// A ray–triangle hit: parameter t along the ray, barycentrics (u, v) of vertices 1 and 2,
/// the triangle's index inside its mesh (prim) and the instance that placed the mesh.
struct Hit {
  float t = std::numeric_limits<float>::infinity();
  float u = 0.0f;
  float v = 0.0f;
  std::uint32_t prim = kInvalidId;
  std::uint32_t instance = kInvalidId;
};

}  // namespace vf
