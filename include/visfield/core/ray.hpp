#pragma once
/// \file Rays and hits: the currency of every query.

#include <cstdint>
#include <limits>

#include "visfield/core/vec.hpp"

namespace vf {

/// Sentinel for "no triangle / no object".
inline constexpr std::uint32_t kInvalidId = 0xffffffffu;

/// Stable identity of an object (an instance) of a Scene: assigned when the object is added, never
/// reused, unchanged when other objects are added, moved or removed.
using ObjectId = std::uint32_t;

/// A ray segment org + t*dir for t in (tmin, tmax]: tmin is exclusive, so a ray that starts on a surface
/// (tmin = 0) does not hit it at t = 0, as in Embree and pbrt; tmax is inclusive. dir need not be unit
/// length (t is in units of |dir|). A ray with a NaN or infinite org or dir, a zero dir, a NaN tmin or
/// tmax, or tmin >= tmax hits nothing in every structure (Ray::is_valid tells).
struct Ray {
  Vec3f org;
  Vec3f dir;
  float tmin = 0.0f;
  float tmax = std::numeric_limits<float>::infinity();

  /// Finite org and dir, dir non-zero, tmin < tmax (tmax may be +infinity, tmin not NaN).
  bool is_valid() const {
    return is_finite(org) && is_finite(dir) && !(dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f) && tmin < tmax &&
           !(tmin != tmin);
  }
};

/// The answer to a closest-hit query. A default-constructed Hit is a miss; found() tells. A hit has a
/// distance t along the ray and the object it belongs to; a triangle hit also names the triangle
/// (prim, barycentrics u, v); an approximate hit (a visibility field) may have no triangle
/// (prim == kInvalidId) but a surface normal. Shading reads `normal`, never the triangle.
struct Hit {
  float t = std::numeric_limits<float>::infinity();  ///< Ray parameter of the hit, in (tmin, tmax].
  float u = 0.0f;                      ///< Barycentric weight of the triangle's vertex 1 (triangle hits).
  float v = 0.0f;                      ///< Barycentric weight of the triangle's vertex 2 (triangle hits).
  std::uint32_t prim = kInvalidId;     ///< Triangle index in its mesh; kInvalidId when the hit has no triangle.
  ObjectId instance = kInvalidId;      ///< Object (instance) hit.
  Vec3f normal{0.0f};                  ///< World-space geometric normal (Embree's Ng) when has_normal: not unit length; for triangles cross(p1 - p0, p2 - p0).
  bool found = false;                  ///< False for a miss: then every other field keeps its default.
  bool has_normal = false;             ///< `normal` is meaningful.

  /// True for a hit, false for a miss.
  constexpr explicit operator bool() const { return found; }
  /// True when the hit names a triangle (exact structures always do).
  constexpr bool has_triangle() const { return found && prim != kInvalidId; }

  /// A triangle hit: distance, barycentrics, triangle, object and the triangle's geometric normal.
  static constexpr Hit triangle(float t, float u, float v, std::uint32_t prim, ObjectId instance, const Vec3f& normal) {
    return Hit{t, u, v, prim, instance, normal, true, true};
  }
  /// A hit without a triangle (approximate structures): distance, object and, when known, a normal.
  static constexpr Hit surface(float t, ObjectId instance, const Vec3f* normal = nullptr) {
    return Hit{t, 0.0f, 0.0f, kInvalidId, instance, normal ? *normal : Vec3f{0.0f}, true, normal != nullptr};
  }
};

}  // namespace vf
