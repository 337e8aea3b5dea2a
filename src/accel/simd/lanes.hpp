#pragma once
/// \file Fixed-width float lanes: one small interface over SSE (4), AVX (8) and AVX-512 (16), with
/// a portable array version for any width or instruction set. Every operation is the IEEE single
/// operation lane by lane (no fused multiply-add, true division), so lane results are bit-identical
/// to the same expression written on scalar floats.

#include <array>
#include <bit>
#include <cstdint>

#if defined(__SSE2__) || defined(__AVX__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace vf::simd {

/// A set of lanes, bit i = lane i.
using LaneBits = std::uint32_t;

/// Portable lanes: plain arrays, one scalar operation per lane. Used where no intrinsics apply.
template <int W>
struct Lanes {
  static constexpr int kWidth = W;
  alignas(W * 4 > 64 ? 64 : W * 4) std::array<float, W> v;

  /// All lanes set to s.
  static Lanes broadcast(float s) {
    Lanes r;
    r.v.fill(s);
    return r;
  }
  /// Loads W floats from p (aligned to the lane width in bytes).
  static Lanes load(const float* p) {
    Lanes r;
    for (int i = 0; i < W; ++i) r.v[i] = p[i];
    return r;
  }
  /// Stores W floats to p.
  void store(float* p) const {
    for (int i = 0; i < W; ++i) p[i] = v[i];
  }
  template <class F>
  static Lanes map(const Lanes& a, const Lanes& b, F f) {
    Lanes r;
    for (int i = 0; i < W; ++i) r.v[i] = f(a.v[i], b.v[i]);
    return r;
  }
  template <class F>
  static LaneBits test(const Lanes& a, const Lanes& b, F f) {
    LaneBits m = 0;
    for (int i = 0; i < W; ++i) m |= (f(a.v[i], b.v[i]) ? 1u : 0u) << i;
    return m;
  }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return map(a, b, [](float x, float y) { return x + y; }); }
  friend Lanes operator-(const Lanes& a, const Lanes& b) { return map(a, b, [](float x, float y) { return x - y; }); }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return map(a, b, [](float x, float y) { return x * y; }); }
  friend Lanes operator/(const Lanes& a, const Lanes& b) { return map(a, b, [](float x, float y) { return x / y; }); }
  /// x86 minps semantics: a < b ? a : b (so b when either is NaN).
  friend Lanes min_nan_second(const Lanes& a, const Lanes& b) {
    return map(a, b, [](float x, float y) { return x < y ? x : y; });
  }
  /// x86 maxps semantics: a > b ? a : b (so b when either is NaN).
  friend Lanes max_nan_second(const Lanes& a, const Lanes& b) {
    return map(a, b, [](float x, float y) { return x > y ? x : y; });
  }
  friend LaneBits cmp_lt(const Lanes& a, const Lanes& b) { return test(a, b, [](float x, float y) { return x < y; }); }
  friend LaneBits cmp_le(const Lanes& a, const Lanes& b) { return test(a, b, [](float x, float y) { return x <= y; }); }
  friend LaneBits cmp_gt(const Lanes& a, const Lanes& b) { return test(a, b, [](float x, float y) { return x > y; }); }
  friend LaneBits cmp_ge(const Lanes& a, const Lanes& b) { return test(a, b, [](float x, float y) { return x >= y; }); }
  friend LaneBits cmp_eq(const Lanes& a, const Lanes& b) { return test(a, b, [](float x, float y) { return x == y; }); }
  /// Lanes where neither a nor b is NaN.
  friend LaneBits cmp_ord(const Lanes& a, const Lanes& b) {
    return test(a, b, [](float x, float y) { return x == x && y == y; });
  }
};

#if defined(__SSE2__)
template <>
struct Lanes<4> {
  static constexpr int kWidth = 4;
  __m128 v;

  static Lanes broadcast(float s) { return {_mm_set1_ps(s)}; }
  static Lanes load(const float* p) { return {_mm_load_ps(p)}; }
  void store(float* p) const { _mm_store_ps(p, v); }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Lanes operator-(const Lanes& a, const Lanes& b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Lanes operator/(const Lanes& a, const Lanes& b) { return {_mm_div_ps(a.v, b.v)}; }
  friend Lanes min_nan_second(const Lanes& a, const Lanes& b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Lanes max_nan_second(const Lanes& a, const Lanes& b) { return {_mm_max_ps(a.v, b.v)}; }
#if defined(__AVX512VL__)
  friend LaneBits cmp_lt(const Lanes& a, const Lanes& b) { return _mm_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ); }
  friend LaneBits cmp_le(const Lanes& a, const Lanes& b) { return _mm_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ); }
  friend LaneBits cmp_gt(const Lanes& a, const Lanes& b) { return _mm_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ); }
  friend LaneBits cmp_ge(const Lanes& a, const Lanes& b) { return _mm_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ); }
  friend LaneBits cmp_eq(const Lanes& a, const Lanes& b) { return _mm_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ); }
  friend LaneBits cmp_ord(const Lanes& a, const Lanes& b) { return _mm_cmp_ps_mask(a.v, b.v, _CMP_ORD_Q); }
#else
  friend LaneBits cmp_lt(const Lanes& a, const Lanes& b) { return LaneBits(_mm_movemask_ps(_mm_cmplt_ps(a.v, b.v))); }
  friend LaneBits cmp_le(const Lanes& a, const Lanes& b) { return LaneBits(_mm_movemask_ps(_mm_cmple_ps(a.v, b.v))); }
  friend LaneBits cmp_gt(const Lanes& a, const Lanes& b) { return LaneBits(_mm_movemask_ps(_mm_cmpgt_ps(a.v, b.v))); }
  friend LaneBits cmp_ge(const Lanes& a, const Lanes& b) { return LaneBits(_mm_movemask_ps(_mm_cmpge_ps(a.v, b.v))); }
  friend LaneBits cmp_eq(const Lanes& a, const Lanes& b) { return LaneBits(_mm_movemask_ps(_mm_cmpeq_ps(a.v, b.v))); }
  friend LaneBits cmp_ord(const Lanes& a, const Lanes& b) { return LaneBits(_mm_movemask_ps(_mm_cmpord_ps(a.v, b.v))); }
#endif
};
#endif

#if defined(__AVX__)
template <>
struct Lanes<8> {
  static constexpr int kWidth = 8;
  __m256 v;

  static Lanes broadcast(float s) { return {_mm256_set1_ps(s)}; }
  static Lanes load(const float* p) { return {_mm256_load_ps(p)}; }
  void store(float* p) const { _mm256_store_ps(p, v); }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend Lanes operator-(const Lanes& a, const Lanes& b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend Lanes operator/(const Lanes& a, const Lanes& b) { return {_mm256_div_ps(a.v, b.v)}; }
  friend Lanes min_nan_second(const Lanes& a, const Lanes& b) { return {_mm256_min_ps(a.v, b.v)}; }
  friend Lanes max_nan_second(const Lanes& a, const Lanes& b) { return {_mm256_max_ps(a.v, b.v)}; }
#if defined(__AVX512VL__)
  friend LaneBits cmp_lt(const Lanes& a, const Lanes& b) { return _mm256_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ); }
  friend LaneBits cmp_le(const Lanes& a, const Lanes& b) { return _mm256_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ); }
  friend LaneBits cmp_gt(const Lanes& a, const Lanes& b) { return _mm256_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ); }
  friend LaneBits cmp_ge(const Lanes& a, const Lanes& b) { return _mm256_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ); }
  friend LaneBits cmp_eq(const Lanes& a, const Lanes& b) { return _mm256_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ); }
  friend LaneBits cmp_ord(const Lanes& a, const Lanes& b) { return _mm256_cmp_ps_mask(a.v, b.v, _CMP_ORD_Q); }
#else
  static LaneBits bits(__m256 m) { return LaneBits(_mm256_movemask_ps(m)); }
  friend LaneBits cmp_lt(const Lanes& a, const Lanes& b) { return bits(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)); }
  friend LaneBits cmp_le(const Lanes& a, const Lanes& b) { return bits(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)); }
  friend LaneBits cmp_gt(const Lanes& a, const Lanes& b) { return bits(_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)); }
  friend LaneBits cmp_ge(const Lanes& a, const Lanes& b) { return bits(_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)); }
  friend LaneBits cmp_eq(const Lanes& a, const Lanes& b) { return bits(_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)); }
  friend LaneBits cmp_ord(const Lanes& a, const Lanes& b) { return bits(_mm256_cmp_ps(a.v, b.v, _CMP_ORD_Q)); }
#endif
};
#endif

#if defined(__AVX512F__)
template <>
struct Lanes<16> {
  static constexpr int kWidth = 16;
  __m512 v;

  static Lanes broadcast(float s) { return {_mm512_set1_ps(s)}; }
  static Lanes load(const float* p) { return {_mm512_load_ps(p)}; }
  void store(float* p) const { _mm512_store_ps(p, v); }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return {_mm512_add_ps(a.v, b.v)}; }
  friend Lanes operator-(const Lanes& a, const Lanes& b) { return {_mm512_sub_ps(a.v, b.v)}; }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return {_mm512_mul_ps(a.v, b.v)}; }
  friend Lanes operator/(const Lanes& a, const Lanes& b) { return {_mm512_div_ps(a.v, b.v)}; }
  // The zero-masking forms with every lane kept: vminps and vmaxps as such (GCC 12's plain forms
  // trip its own uninitialised-value warning).
  friend Lanes min_nan_second(const Lanes& a, const Lanes& b) { return {_mm512_maskz_min_ps(0xffff, a.v, b.v)}; }
  friend Lanes max_nan_second(const Lanes& a, const Lanes& b) { return {_mm512_maskz_max_ps(0xffff, a.v, b.v)}; }
  friend LaneBits cmp_lt(const Lanes& a, const Lanes& b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ); }
  friend LaneBits cmp_le(const Lanes& a, const Lanes& b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ); }
  friend LaneBits cmp_gt(const Lanes& a, const Lanes& b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ); }
  friend LaneBits cmp_ge(const Lanes& a, const Lanes& b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ); }
  friend LaneBits cmp_eq(const Lanes& a, const Lanes& b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ); }
  friend LaneBits cmp_ord(const Lanes& a, const Lanes& b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_ORD_Q); }
};
#endif

/// Index of the lowest set lane; bits must be non-zero.
inline int first_lane(LaneBits bits) { return std::countr_zero(bits); }

/// Widest lane count with native support in this build (16 with AVX-512, 8 with AVX, else 4).
#if defined(__AVX512F__)
inline constexpr int kNativeWidth = 16;
#elif defined(__AVX__)
inline constexpr int kNativeWidth = 8;
#else
inline constexpr int kNativeWidth = 4;
#endif

}  // namespace vf::simd
