#pragma once
/// \file The conservative ray-box test of the 8-wide BVH nodes (private to the accel module).
///
/// Box tests are conservative (Ize 2013, "Robust BVH ray traversal"): the far distances are scaled
/// by 1 + 2^-16, more than the 1 + 2*gamma(4) that covers the rounding of the subtraction, the
/// reciprocal, the product and the scaling itself, so a box the ray enters is never culled because
/// of rounding; the rest is slack for the triangle test's own rounding (see also the box margin in
/// collapse.cpp). A zero direction component gives an infinite reciprocal; the resulting
/// 0 * inf = NaN (origin exactly on a slab plane) is discarded by ordering the min/max operands so
/// that the running interval wins, i.e. that axis does not restrict the interval, which is exact:
/// such a ray stays in the plane. Scaling moves a far distance below zero down, not up: boxes wholly
/// behind the origin are met only by an interval that starts there (tmin < 0), whose far distances
/// are also scaled by 1 - 2^-16 and the larger product kept. The t interval a box must meet is the ray's, widened by a relative
/// 2^-16 (widen_down, widen_up), so that a triangle whose computed t lies a few ulps outside its
/// box's exact interval is still tested.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "bvh/wide_nodes.hpp"
#include "visfield/core/ray.hpp"
#include "simd/lanes.hpp"

namespace vf::bvh {

using V8 = simd::Lanes<8>;

inline constexpr float kFarScale = 1.0f + 0x1p-16f;
/// The scale that moves a far distance below zero up by as much.
inline constexpr float kFarScaleBehind = 1.0f - 0x1p-16f;
inline constexpr float kIntervalSlack = 0x1p-16f;

/// t moved down by the relative slack (infinities unchanged).
inline float widen_down(float t) { return std::isfinite(t) ? t - std::fabs(t) * kIntervalSlack : t; }
/// t moved up by the relative slack (infinities unchanged).
inline float widen_up(float t) { return std::isfinite(t) ? t + std::fabs(t) * kIntervalSlack : t; }

/// 1 / d for the box test: +-inf for +-0, and NaN where a non-zero d is so small that 1 / d
/// overflows. Such a component's slab distances would be infinite where the true ones are finite
/// (a ray reaching a plane 1e-45 away at 1e-45 a unit meets it at t = 1); NaN ones leave the
/// interval unrestricted, which is conservative.
inline float box_reciprocal(float d) {
  const float inv = 1.0f / d;
  return d != 0.0f && std::isinf(inv) ? std::copysign(std::numeric_limits<float>::quiet_NaN(), d) : inv;
}

/// Per-ray constants of the box test.
struct BoxRay {
  // Scalars, broadcast where a node's boxes are tested: a stream keeps a run of rays' constants at
  // hand, which as 8-lane copies filled the first-level cache.
  float org[3], inv[3];
  int near_row[3], far_row[3];

  /// Fills the constants for `ray` given inv_dir[a] = 1 / ray.dir[a] (+-inf for +-0); an overflowed
  /// reciprocal becomes box_reciprocal()'s NaN.
  void set(const Ray& ray, const float* inv_dir) {
    for (int a = 0; a < 3; ++a) {
      org[a] = ray.org[a];
      inv[a] = ray.dir[a] != 0.0f && std::isinf(inv_dir[a]) ? std::copysign(std::numeric_limits<float>::quiet_NaN(), inv_dir[a]) : inv_dir[a];
      const int negative = std::signbit(ray.dir[a]) ? 3 : 0;
      near_row[a] = kLoX + a + negative;
      far_row[a] = kHiX + a - negative;
    }
  }
  /// Fills the constants for a ray from `org` whose direction has the reciprocals `inv_dir`
  /// (box_reciprocal()'s): the same as set(ray, inv_dir), the direction's signs being the reciprocals'.
  void set(const float* org_xyz, const float* inv_dir) {
    for (int a = 0; a < 3; ++a) {
      org[a] = org_xyz[a];
      inv[a] = inv_dir[a];
      const int negative = std::signbit(inv_dir[a]) ? 3 : 0;
      near_row[a] = kLoX + a + negative;
      far_row[a] = kHiX + a - negative;
    }
  }
};

/// Lanes of the children of `node` whose boxes meet [tmin, tmax] (already widened); their entry
/// distances go to `t_near`.
inline simd::LaneBits test_children(const Node8& node, const BoxRay& r, const V8& tmin, const V8& tmax, V8& t_near) {
  const auto slab = [&](int row, int axis) { return (V8::load(node.bounds[row]) - V8::broadcast(r.org[axis])) * V8::broadcast(r.inv[axis]); };
  const V8 nx = slab(r.near_row[0], 0), ny = slab(r.near_row[1], 1), nz = slab(r.near_row[2], 2);
  const V8 fx = slab(r.far_row[0], 0), fy = slab(r.far_row[1], 1), fz = slab(r.far_row[2], 2);
  // The running value is the second operand, so a NaN slab value leaves it unchanged. Scaling after
  // the minimum scales every far slab value (and tmax, which only loosens the test further).
  t_near = max_nan_second(nx, max_nan_second(ny, max_nan_second(nz, tmin)));
  const V8 far = min_nan_second(fx, min_nan_second(fy, min_nan_second(fz, tmax)));
  V8 t_far = far * V8::broadcast(kFarScale);
  if (cmp_lt(tmin, V8::broadcast(0.0f)) != 0) t_far = max_nan_second(far * V8::broadcast(kFarScaleBehind), t_far);
  return cmp_le(t_near, t_far);
}

#if defined(__AVX512F__) && defined(__AVX512DQ__)
/// A ray in each of 16 lanes, as columns: origin x, y, z, the direction's reciprocals x, y, z (+-inf
/// for +-0), and [tmin, tmax] widened.
struct BoxRays16 {
  __m512 org[3], inv[3], tmin, tmax;
  __mmask16 negative[3];  // lanes whose reciprocal on the axis is negative (its sign bit)
  bool behind = false;    // some lane's interval starts behind its origin

  /// Loads 16 rays from columns: org x, y, z, dir x, y, z, tmin, tmax (as given: widened here), each at `at`.
  void load(const float* const columns[8], std::size_t at) {
    load_lines(columns, at);
    tmin = widen16(_mm512_loadu_ps(columns[6] + at), -1.0f);
    tmax = widen16(_mm512_loadu_ps(columns[7] + at), 1.0f);
    behind = _mm512_cmp_ps_mask(tmin, _mm512_setzero_ps(), _CMP_LT_OQ) != 0;
  }
  /// Loads 16 rays' origins and directions from columns 0 .. 5 at `at`; every ray's interval is
  /// (shared_tmin, shared_tmax), already widened.
  void load(const float* const columns[6], std::size_t at, float shared_tmin, float shared_tmax) {
    load_lines(columns, at);
    tmin = _mm512_set1_ps(shared_tmin);
    tmax = _mm512_set1_ps(shared_tmax);
    behind = shared_tmin < 0.0f;
  }

 private:
  /// widen_down() (`sign` −1) or widen_up() (+1) on 16 lanes, bit for bit: the same product and sum
  /// where t is finite.
  static __m512 widen16(__m512 t, float sign) {
    const __mmask16 finite = static_cast<__mmask16>(~_mm512_fpclass_ps_mask(t, 0x99));  // 0x99: NaN or +-inf
    const __m512 slack = _mm512_mul_ps(_mm512_abs_ps(t), _mm512_set1_ps(kIntervalSlack));
    return sign < 0.0f ? _mm512_mask_sub_ps(t, finite, t, slack) : _mm512_mask_add_ps(t, finite, t, slack);
  }
  /// The origins from columns 0 .. 2 at `at`, and the reciprocals (1 / x, as BoxRay::set's) of the
  /// directions in columns 3 .. 5, with their signs.
  void load_lines(const float* const columns[6], std::size_t at) {
    for (int a = 0; a < 3; ++a) {
      org[a] = _mm512_loadu_ps(columns[a] + at);
      const __m512 dir = _mm512_loadu_ps(columns[3 + a] + at);
      inv[a] = _mm512_div_ps(_mm512_set1_ps(1.0f), dir);  // +-inf for +-0
      negative[a] = _mm512_movepi32_mask(_mm512_castps_si512(inv[a]));
      // box_reciprocal(): NaN where a non-zero direction's reciprocal overflowed.
      const __mmask16 overflowed = _mm512_fpclass_ps_mask(inv[a], 0x18) & _mm512_cmp_ps_mask(dir, _mm512_setzero_ps(), _CMP_NEQ_OQ);
      inv[a] = _mm512_mask_mov_ps(inv[a], overflowed, _mm512_set1_ps(std::numeric_limits<float>::quiet_NaN()));
    }
  }
};

/// test_children() with the roles turned: 16 rays against the box of one child `slot`. The same
/// operations on the same values for each ray, so lane i is bit `slot` of test_children() for ray i.
inline __mmask16 rays_meet_child(const Node8& node, int slot, const BoxRays16& r) {
  __m512 t_near = r.tmin, t_far = r.tmax;
  // Innermost first, as test_children() nests them: z, then y, then x, the running value second.
  for (int a = 2; a >= 0; --a) {
    const __m512 lo = _mm512_set1_ps(node.bounds[kLoX + a][slot]), hi = _mm512_set1_ps(node.bounds[kHiX + a][slot]);
    const __m512 near_plane = _mm512_mask_blend_ps(r.negative[a], lo, hi), far_plane = _mm512_mask_blend_ps(r.negative[a], hi, lo);
    // The zero-masking forms with every lane kept: vmaxps and vminps as such (GCC 12's plain forms
    // trip its own uninitialised-value warning).
    t_near = _mm512_maskz_max_ps(0xffff, _mm512_mul_ps(_mm512_sub_ps(near_plane, r.org[a]), r.inv[a]), t_near);
    t_far = _mm512_maskz_min_ps(0xffff, _mm512_mul_ps(_mm512_sub_ps(far_plane, r.org[a]), r.inv[a]), t_far);
  }
  __m512 scaled = _mm512_mul_ps(t_far, _mm512_set1_ps(kFarScale));
  if (r.behind) scaled = _mm512_maskz_max_ps(0xffff, _mm512_mul_ps(t_far, _mm512_set1_ps(kFarScaleBehind)), scaled);
  return _mm512_cmp_ps_mask(t_near, scaled, _CMP_LE_OQ);
}
#endif

#if defined(__AVX2__)
/// BoxRays16 on 8 AVX2 lanes: the same columns, the same operations.
struct BoxRays8 {
  __m256 org[3], inv[3], tmin, tmax;  // a reciprocal's sign bit says the axis is negative
  bool behind = false;                 // some lane's interval starts behind its origin

  /// Loads 8 rays from columns: org x, y, z, dir x, y, z, tmin, tmax (as given: widened here), each at `at`.
  void load(const float* const columns[8], std::size_t at) {
    load_lines(columns, at);
    tmin = widen8(_mm256_loadu_ps(columns[6] + at), -1.0f);
    tmax = widen8(_mm256_loadu_ps(columns[7] + at), 1.0f);
    behind = _mm256_movemask_ps(_mm256_cmp_ps(tmin, _mm256_setzero_ps(), _CMP_LT_OQ)) != 0;
  }
  /// Loads 8 rays' origins and directions from columns 0 .. 5 at `at`; every ray's interval is
  /// (shared_tmin, shared_tmax), already widened.
  void load(const float* const columns[6], std::size_t at, float shared_tmin, float shared_tmax) {
    load_lines(columns, at);
    tmin = _mm256_set1_ps(shared_tmin);
    tmax = _mm256_set1_ps(shared_tmax);
    behind = shared_tmin < 0.0f;
  }

 private:
  /// widen_down() (`sign` −1) or widen_up() (+1) on 8 lanes, bit for bit.
  static __m256 widen8(__m256 t, float sign) {
    const __m256 magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), t);
    const __m256 finite = _mm256_cmp_ps(magnitude, _mm256_set1_ps(INFINITY), _CMP_LT_OQ);  // false for NaN and +-inf
    const __m256 slack = _mm256_mul_ps(magnitude, _mm256_set1_ps(kIntervalSlack));
    return _mm256_blendv_ps(t, sign < 0.0f ? _mm256_sub_ps(t, slack) : _mm256_add_ps(t, slack), finite);
  }
  void load_lines(const float* const columns[6], std::size_t at) {
    for (int a = 0; a < 3; ++a) {
      org[a] = _mm256_loadu_ps(columns[a] + at);
      const __m256 dir = _mm256_loadu_ps(columns[3 + a] + at);
      inv[a] = _mm256_div_ps(_mm256_set1_ps(1.0f), dir);  // +-inf for +-0
      // box_reciprocal(): NaN where a non-zero direction's reciprocal overflowed (the sign bit kept).
      const __m256 magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), inv[a]);
      const __m256 overflowed = _mm256_and_ps(_mm256_cmp_ps(magnitude, _mm256_set1_ps(INFINITY), _CMP_EQ_OQ),
                                              _mm256_cmp_ps(dir, _mm256_setzero_ps(), _CMP_NEQ_OQ));
      inv[a] = _mm256_blendv_ps(inv[a], _mm256_or_ps(inv[a], _mm256_set1_ps(std::numeric_limits<float>::quiet_NaN())), overflowed);
    }
  }
};

/// rays_meet_child() for 8 rays: lane i is bit `slot` of test_children() for ray i.
inline std::uint32_t rays_meet_child(const Node8& node, int slot, const BoxRays8& r) {
  __m256 t_near = r.tmin, t_far = r.tmax;
  for (int a = 2; a >= 0; --a) {
    const __m256 lo = _mm256_set1_ps(node.bounds[kLoX + a][slot]), hi = _mm256_set1_ps(node.bounds[kHiX + a][slot]);
    // blendv picks by the reciprocal's sign bit: the far side first where the axis is negative.
    const __m256 near_plane = _mm256_blendv_ps(lo, hi, r.inv[a]), far_plane = _mm256_blendv_ps(hi, lo, r.inv[a]);
    t_near = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(near_plane, r.org[a]), r.inv[a]), t_near);
    t_far = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(far_plane, r.org[a]), r.inv[a]), t_far);
  }
  __m256 scaled = _mm256_mul_ps(t_far, _mm256_set1_ps(kFarScale));
  if (r.behind) scaled = _mm256_max_ps(_mm256_mul_ps(t_far, _mm256_set1_ps(kFarScaleBehind)), scaled);
  const __m256 meets = _mm256_cmp_ps(t_near, scaled, _CMP_LE_OQ);
  return static_cast<std::uint32_t>(_mm256_movemask_ps(meets));
}
#endif

}  // namespace vf::bvh
