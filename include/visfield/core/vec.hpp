#pragma once
/// \file Small fixed-size vector math used everywhere (float, 3 components).

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "visfield/core/orthonormal_basis.hpp"

namespace vf {

/// A 3-component float vector: positions, directions, colours. Plain value type.
struct Vec3f {
  float x = 0, y = 0, z = 0;

  constexpr Vec3f() = default;
  constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  /// Broadcast constructor: (s, s, s).
  constexpr explicit Vec3f(float s) : x(s), y(s), z(s) {}

  /// Component by index 0..2 (no bounds check).
  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  /// Mutable component by index 0..2 (no bounds check).
  constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3f operator-() const { return {-x, -y, -z}; }
  constexpr Vec3f& operator+=(const Vec3f& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3f& operator-=(const Vec3f& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3f& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
  constexpr bool operator==(const Vec3f&) const = default;
};

constexpr Vec3f operator+(Vec3f a, const Vec3f& b) { return a += b; }
constexpr Vec3f operator-(Vec3f a, const Vec3f& b) { return a -= b; }
constexpr Vec3f operator*(Vec3f a, float s) { return a *= s; }
constexpr Vec3f operator*(float s, Vec3f a) { return a *= s; }
/// Component-wise product.
constexpr Vec3f operator*(const Vec3f& a, const Vec3f& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3f operator/(const Vec3f& a, float s) { return {a.x / s, a.y / s, a.z / s}; }

/// Dot product.
constexpr float dot(const Vec3f& a, const Vec3f& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// Cross product (right-handed).
constexpr Vec3f cross(const Vec3f& a, const Vec3f& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Euclidean length.
inline float length(const Vec3f& a) { return std::sqrt(dot(a, a)); }
/// Unit vector along `a`; `a` must be non-zero.
inline Vec3f normalize(const Vec3f& a) { return a * (1.0f / length(a)); }
/// Component-wise minimum.
constexpr Vec3f min(const Vec3f& a, const Vec3f& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
/// Component-wise maximum.
constexpr Vec3f max(const Vec3f& a, const Vec3f& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
/// Component-wise absolute value.
inline Vec3f abs(const Vec3f& a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
/// Largest component.
constexpr float max_component(const Vec3f& a) { return std::max(a.x, std::max(a.y, a.z)); }
/// Index (0..2) of the component with the largest value.
constexpr int max_axis(const Vec3f& a) { return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2); }
/// True when every component is finite (no NaN or Inf).
inline bool is_finite(const Vec3f& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

/// Builds an orthonormal basis (t, b) around unit normal n: orthonormal_basis.hpp's, for Vec3f.
inline void orthonormal_basis(const Vec3f& n, Vec3f& t, Vec3f& b) {
  const OrthonormalBasis<float> basis = orthonormal_basis(hd::Vec3<float>{n.x, n.y, n.z});
  t = {basis.u.x, basis.u.y, basis.u.z};
  b = {basis.v.x, basis.v.y, basis.v.z};
}

}  // namespace vf
