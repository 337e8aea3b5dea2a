#pragma once
/// \file Rigid transforms with uniform scale, used by instances.

#include <array>

#include "visfield/core/bounds.hpp"
#include "visfield/core/vec.hpp"

namespace vf {

/// Row-major 3x3 matrix.
struct Mat3 {
  std::array<Vec3f, 3> rows{Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}};

  /// Matrix-vector product.
  constexpr Vec3f operator*(const Vec3f& v) const { return {dot(rows[0], v), dot(rows[1], v), dot(rows[2], v)}; }
  /// Matrix product.
  Mat3 operator*(const Mat3& o) const;
  /// Transpose (the inverse of a rotation).
  Mat3 transposed() const;
  /// Rotation by `degrees` about unit `axis` (right-handed, Rodrigues).
  static Mat3 rotation(const Vec3f& axis, float degrees);
  /// Rotation from XYZ Euler angles in degrees, applied X first, then Y, then Z.
  static Mat3 euler_xyz(const Vec3f& degrees);
};

/// x -> scale * (R x) + translation, with R a rotation and scale > 0 (rotation, translation, uniform scale).
struct Transform {
  Mat3 rotation;
  Vec3f translation{0.0f};
  float scale = 1.0f;

  /// Maps an object-space point to world space.
  Vec3f apply_point(const Vec3f& p) const { return rotation * p * scale + translation; }
  /// Maps an object-space direction to world space (scaled, not normalised).
  Vec3f apply_vector(const Vec3f& v) const { return rotation * v * scale; }
  /// Maps a world-space point back to object space.
  Vec3f inverse_point(const Vec3f& p) const { return rotation.transposed() * (p - translation) * (1.0f / scale); }
  /// World bounds of an object-space box (the 8 corners transformed).
  Bounds3f apply_bounds(const Bounds3f& b) const;
};

}  // namespace vf
