#pragma once
/// \file Rigid transforms with uniform scale, used by instances.

#include <array>

#include "visfield/core/bounds.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/vec.hpp"

namespace vf {

/// Row-major 3x3 matrix.
struct Mat3 {
  std::array<Vec3f, 3> rows{Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}};

  /// Element-wise equality.
  bool operator==(const Mat3&) const = default;

  /// Matrix-vector product.
  constexpr Vec3f operator*(const Vec3f& v) const { return {dot(rows[0], v), dot(rows[1], v), dot(rows[2], v)}; }
  /// Matrix product.
  Mat3 operator*(const Mat3& o) const;
  /// Every element multiplied by `s`.
  Mat3 scaled(float s) const;
  /// Transpose (the inverse of a rotation).
  Mat3 transposed() const;
  /// Exactly the identity matrix.
  bool is_identity() const;
  /// Rotation by `degrees` about unit `axis` (right-handed, Rodrigues).
  static Mat3 rotation(const Vec3f& axis, float degrees);
  /// Rotation from XYZ Euler angles in degrees, applied X first, then Y, then Z.
  static Mat3 euler_xyz(const Vec3f& degrees);
};

/// The inverse of a Transform, precomputed once to map world-space rays into object space: the
/// object-space ray has the same parameter t for the same point. Plain value; thread-safe.
struct InverseTransform {
  Mat3 linear;             ///< R^T / scale.
  Vec3f translation{0.0f}; ///< The forward translation, subtracted first.
  bool identity = true;    ///< Exactly the identity: rays pass through bit for bit.

  /// `ray` in object space (tmin, tmax unchanged). O(1).
  Ray apply(const Ray& ray) const {
    if (identity) return ray;
    return Ray{linear * (ray.org - translation), linear * ray.dir, ray.tmin, ray.tmax};
  }
};

/// x -> scale * (R x) + translation, with R a rotation and scale > 0 (rotation, translation, uniform scale).
struct Transform {
  Mat3 rotation;
  Vec3f translation{0.0f};
  float scale = 1.0f;

  /// Element-wise equality (the same map written the same way).
  bool operator==(const Transform&) const = default;

  /// Maps an object-space point to world space.
  Vec3f apply_point(const Vec3f& p) const { return rotation * p * scale + translation; }
  /// Maps an object-space direction to world space (scaled, not normalised).
  Vec3f apply_vector(const Vec3f& v) const { return rotation * v * scale; }
  /// Maps the cross product of two object-space edges to the cross product of the world-space edges
  /// (R n scale^2): how a triangle's geometric normal moves with its object.
  Vec3f apply_normal(const Vec3f& n) const { return rotation * n * (scale * scale); }
  /// The inverse map, for rays (see InverseTransform).
  InverseTransform inverse() const;
  /// World bounds of an object-space box (the 8 corners transformed).
  Bounds3f apply_bounds(const Bounds3f& b) const;
  /// Exactly the identity (rotation identity, no translation, scale 1).
  bool is_identity() const;
  /// Finite entries, a finite scale > 0, and a rotation part that is a rotation: orthonormal rows
  /// (to 1e-4) and determinant +1 (no mirroring, no shear, no singular matrix).
  bool is_valid() const;
};

}  // namespace vf
