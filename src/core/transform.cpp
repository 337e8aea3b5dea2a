#include "visfield/core/transform.hpp"

#include <cmath>
#include <numbers>

namespace vf {

Mat3 Mat3::operator*(const Mat3& o) const {
  const Mat3 t = o.transposed();
  Mat3 r;
  for (int i = 0; i < 3; ++i) r.rows[i] = {dot(rows[i], t.rows[0]), dot(rows[i], t.rows[1]), dot(rows[i], t.rows[2])};
  return r;
}

Mat3 Mat3::scaled(float s) const {
  Mat3 r;
  for (int i = 0; i < 3; ++i) r.rows[i] = rows[i] * s;
  return r;
}

Mat3 Mat3::transposed() const {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.rows[i][j] = rows[j][i];
  return r;
}

bool Mat3::is_identity() const { return rows == Mat3{}.rows; }

Mat3 Mat3::rotation(const Vec3f& axis, float degrees) {
  const Vec3f k = normalize(axis);
  const float a = degrees * std::numbers::pi_v<float> / 180.0f;
  const float c = std::cos(a), s = std::sin(a), C = 1.0f - c;
  Mat3 r;
  r.rows[0] = {c + k.x * k.x * C, k.x * k.y * C - k.z * s, k.x * k.z * C + k.y * s};
  r.rows[1] = {k.y * k.x * C + k.z * s, c + k.y * k.y * C, k.y * k.z * C - k.x * s};
  r.rows[2] = {k.z * k.x * C - k.y * s, k.z * k.y * C + k.x * s, c + k.z * k.z * C};
  return r;
}

Mat3 Mat3::euler_xyz(const Vec3f& degrees) {
  return rotation({0, 0, 1}, degrees.z) * rotation({0, 1, 0}, degrees.y) * rotation({1, 0, 0}, degrees.x);
}

InverseTransform Transform::inverse() const {
  InverseTransform inv;
  inv.identity = is_identity();
  inv.linear = rotation.transposed().scaled(1.0f / scale);
  inv.translation = translation;
  return inv;
}

Bounds3f Transform::apply_bounds(const Bounds3f& b) const {
  Bounds3f out;
  if (b.empty()) return out;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3f p{(corner & 1) ? b.hi.x : b.lo.x, (corner & 2) ? b.hi.y : b.lo.y, (corner & 4) ? b.hi.z : b.lo.z};
    out.extend(apply_point(p));
  }
  return out;
}

bool Transform::is_identity() const { return rotation.is_identity() && translation == Vec3f{0.0f} && scale == 1.0f; }

bool Transform::is_valid() const {
  for (const Vec3f& row : rotation.rows)
    if (!is_finite(row)) return false;
  if (!(is_finite(translation) && std::isfinite(scale) && scale > 0.0f)) return false;
  constexpr float kTolerance = 1e-4f;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::fabs(dot(rotation.rows[i], rotation.rows[j]) - (i == j ? 1.0f : 0.0f)) > kTolerance) return false;
  return dot(cross(rotation.rows[0], rotation.rows[1]), rotation.rows[2]) > 0.0f;
}

}  // namespace vf
