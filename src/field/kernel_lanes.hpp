#pragma once
// Lanes for the ObjectField batch kernel (field_kernel.hpp): float lanes, 32-bit integer lanes and
// native masks, with gathers, in two backends of one interface — 16 lanes on AVX-512 and 8 on AVX2 —
// and Pair, two packets of either side by side, so the kernel is written once. The triangle tests'
// lanes (src/accel/simd/lanes.hpp) stay float-only with bit masks; this kernel computes table
// indices and reads tables, which needs integer lanes, gathers and masks that select without a
// round trip through bits.
//
// Every float operation is the IEEE single operation, and fma() the IEEE fused multiply-add that
// field_query.hpp writes as hd::fma, so a lane computes exactly what it computes for one ray. The
// AVX2 backend therefore needs the FMA extension too (every AVX2 CPU but a few has it).

#include <cstdint>

#if defined(__AVX2__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "visfield/core/lane_compress.hpp"
#include "visfield/core/row_transpose.hpp"

namespace vf::field::lanes {

#if defined(__AVX512F__)
/// 16 lanes on AVX-512F.
struct Avx512 {
  static constexpr int kWidth = 16;
  struct M {
    __mmask16 m;
  };
  struct F {
    __m512 v;
  };
  struct I {
    __m512i v;
  };
  static F splat(float x) { return {_mm512_set1_ps(x)}; }
  static I splat(int x) { return {_mm512_set1_epi32(x)}; }
  static F load(const float* p) { return {_mm512_loadu_ps(p)}; }
  static I load(const std::uint32_t* p) { return {_mm512_loadu_si512(p)}; }
  static I lane_index() { return {_mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)}; }
  static void store(float* p, F a) { _mm512_storeu_ps(p, a.v); }
  static void store(std::int32_t* p, I a) { _mm512_storeu_si512(p, a.v); }
  static std::uint32_t bits(M a) { return a.m; }
  static M none() { return {0}; }
  static M all() { return {0xFFFF}; }
  /// Writes the lanes of `m` of `values` to dst[0 ..), in lane order, and may write up to 16 values
  /// there (dst needs room for 16); returns how many it kept. (A register compress and a plain store:
  /// the memory form of vpcompressd is microcoded and slow on AMD Zen 4.) Integer or float lanes.
  static int compress(std::uint32_t* dst, I values, M m) {
    _mm512_storeu_si512(dst, _mm512_maskz_compress_epi32(m.m, values.v));
    return __builtin_popcount(m.m);
  }
  static int compress(float* dst, F values, M m) {
    _mm512_storeu_ps(dst, _mm512_maskz_compress_ps(m.m, values.v));
    return __builtin_popcount(m.m);
  }
  /// p[lane] = 1 for the lanes of `m`; the other bytes of p[0 .. 16) keep their values.
  static void set_bytes(std::uint8_t* p, M m) {
#if defined(__AVX512BW__) && defined(__AVX512VL__)
    _mm_mask_storeu_epi8(p, m.m, _mm_set1_epi8(1));
#else
    for (std::uint32_t lanes = m.m; lanes != 0; lanes &= lanes - 1) p[__builtin_ctz(lanes)] = 1;
#endif
  }
  /// The 8 columns of 16 consecutive rows of 8 floats at `p` (column c, lane l = p[8l + c]).
  static void transpose_rows(const float* p, F column[8]) {
    __m512 c[8];
    simd::rows_to_columns16(p, c);
    for (int k = 0; k < 8; ++k) column[k].v = c[k];
  }
  /// The 8 columns of the rows of 8 floats at base + 8·index[l], l < 16: a gather a column.
  static void transpose_rows_at(const float* base, const std::uint32_t* index, F column[8]) {
    const __m512i slot = _mm512_slli_epi32(_mm512_loadu_si512(index), 3);
    for (int k = 0; k < 8; ++k) column[k].v = _mm512_mask_i32gather_ps(_mm512_setzero_ps(), 0xffff, slot, base + k, 4);
  }
};

inline Avx512::M operator&(Avx512::M a, Avx512::M b) { return {static_cast<__mmask16>(a.m & b.m)}; }
inline Avx512::M operator|(Avx512::M a, Avx512::M b) { return {static_cast<__mmask16>(a.m | b.m)}; }
inline Avx512::M operator~(Avx512::M a) { return {static_cast<__mmask16>(~a.m)}; }
inline Avx512::M operator^(Avx512::M a, Avx512::M b) { return {static_cast<__mmask16>(a.m ^ b.m)}; }
inline bool any(Avx512::M a) { return a.m != 0; }

inline Avx512::F operator+(Avx512::F a, Avx512::F b) { return {_mm512_add_ps(a.v, b.v)}; }
inline Avx512::F operator-(Avx512::F a, Avx512::F b) { return {_mm512_sub_ps(a.v, b.v)}; }
inline Avx512::F operator*(Avx512::F a, Avx512::F b) { return {_mm512_mul_ps(a.v, b.v)}; }
inline Avx512::F operator/(Avx512::F a, Avx512::F b) { return {_mm512_div_ps(a.v, b.v)}; }
inline Avx512::F operator-(Avx512::F a) {
  return {_mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a.v), _mm512_set1_epi32(static_cast<int>(0x80000000u))))};
}
inline Avx512::M operator<(Avx512::F a, Avx512::F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)}; }
inline Avx512::M operator<=(Avx512::F a, Avx512::F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)}; }
inline Avx512::M operator>(Avx512::F a, Avx512::F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)}; }
inline Avx512::M operator>=(Avx512::F a, Avx512::F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)}; }
inline Avx512::M operator==(Avx512::F a, Avx512::F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ)}; }
inline Avx512::F sqrt(Avx512::F a) { return {_mm512_sqrt_ps(a.v)}; }
/// a·b + c rounded once (hd::fma).
inline Avx512::F fma(Avx512::F a, Avx512::F b, Avx512::F c) { return {_mm512_fmadd_ps(a.v, b.v, c.v)}; }
inline Avx512::F abs(Avx512::F a) { return {_mm512_abs_ps(a.v)}; }
inline Avx512::F floor(Avx512::F a) { return {_mm512_roundscale_ps(a.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)}; }
/// a > b ? a : b (b when either is NaN).
inline Avx512::F max(Avx512::F a, Avx512::F b) { return {_mm512_max_ps(a.v, b.v)}; }
/// a < b ? a : b (b when either is NaN).
inline Avx512::F min(Avx512::F a, Avx512::F b) { return {_mm512_min_ps(a.v, b.v)}; }
/// |magnitude| with the sign bit of `sign`.
inline Avx512::F copysign(Avx512::F magnitude, Avx512::F sign) {
  const __m512i bit = _mm512_set1_epi32(static_cast<int>(0x80000000u));
  return {_mm512_castsi512_ps(_mm512_or_si512(_mm512_andnot_si512(bit, _mm512_castps_si512(magnitude.v)),
                                             _mm512_and_si512(bit, _mm512_castps_si512(sign.v))))};
}
inline Avx512::F select(Avx512::M m, Avx512::F a, Avx512::F b) { return {_mm512_mask_blend_ps(m.m, b.v, a.v)}; }
inline Avx512::I select(Avx512::M m, Avx512::I a, Avx512::I b) { return {_mm512_mask_blend_epi32(m.m, b.v, a.v)}; }
/// Truncation towards zero (C's float-to-int conversion).
inline Avx512::I to_int(Avx512::F a) { return {_mm512_cvttps_epi32(a.v)}; }
inline Avx512::F to_float(Avx512::I a) { return {_mm512_cvtepi32_ps(a.v)}; }

inline Avx512::I operator+(Avx512::I a, Avx512::I b) { return {_mm512_add_epi32(a.v, b.v)}; }
inline Avx512::I operator-(Avx512::I a, Avx512::I b) { return {_mm512_sub_epi32(a.v, b.v)}; }
inline Avx512::I operator*(Avx512::I a, Avx512::I b) { return {_mm512_mullo_epi32(a.v, b.v)}; }
inline Avx512::I operator&(Avx512::I a, Avx512::I b) { return {_mm512_and_si512(a.v, b.v)}; }
inline Avx512::I operator|(Avx512::I a, Avx512::I b) { return {_mm512_or_si512(a.v, b.v)}; }
inline Avx512::I operator<<(Avx512::I a, Avx512::I b) { return {_mm512_sllv_epi32(a.v, b.v)}; }
inline Avx512::I operator>>(Avx512::I a, Avx512::I b) { return {_mm512_srlv_epi32(a.v, b.v)}; }
inline Avx512::M operator<(Avx512::I a, Avx512::I b) { return {_mm512_cmplt_epi32_mask(a.v, b.v)}; }
inline Avx512::M operator<=(Avx512::I a, Avx512::I b) { return {_mm512_cmple_epi32_mask(a.v, b.v)}; }
inline Avx512::M operator==(Avx512::I a, Avx512::I b) { return {_mm512_cmpeq_epi32_mask(a.v, b.v)}; }
inline Avx512::I min(Avx512::I a, Avx512::I b) { return {_mm512_min_epi32(a.v, b.v)}; }
inline Avx512::I max(Avx512::I a, Avx512::I b) { return {_mm512_max_epi32(a.v, b.v)}; }
inline Avx512::I abs(Avx512::I a) { return {_mm512_abs_epi32(a.v)}; }

/// base[index] for the lanes of `m`, 0 elsewhere.
inline Avx512::F gather(const float* base, Avx512::I index, Avx512::M m) {
  return {_mm512_mask_i32gather_ps(_mm512_setzero_ps(), m.m, index.v, base, 4)};
}
/// The 32 bits at byte offset `offset` from `base` for the lanes of `m`, 0 elsewhere.
inline Avx512::I gather_bytes(const void* base, Avx512::I offset, Avx512::M m) {
  return {_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m.m, offset.v, base, 1)};
}
/// The two floats of table[index] (64 bits each; every lane's index valid): the low one into
/// `first`, the high one into `second` (two 8-lane 64-bit gathers, then two permutes).
inline void gather_pairs(const unsigned long long* table, Avx512::I index, Avx512::F& first, Avx512::F& second) {
  const __m512 lo = _mm512_castsi512_ps(_mm512_i32gather_epi64(_mm512_castsi512_si256(index.v), table, 8));
  const __m512 hi = _mm512_castsi512_ps(_mm512_i32gather_epi64(_mm512_extracti64x4_epi64(index.v, 1), table, 8));
  first.v = _mm512_permutex2var_ps(lo, _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30), hi);
  second.v = _mm512_permutex2var_ps(lo, _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31), hi);
}
#endif

#if defined(__AVX2__) && defined(__FMA__)
/// 8 lanes on AVX2 (masks are lanes of all ones or all zeros).
struct Avx2 {
  static constexpr int kWidth = 8;
  struct M {
    __m256i m;
  };
  struct F {
    __m256 v;
  };
  struct I {
    __m256i v;
  };
  static F splat(float x) { return {_mm256_set1_ps(x)}; }
  static I splat(int x) { return {_mm256_set1_epi32(x)}; }
  static F load(const float* p) { return {_mm256_loadu_ps(p)}; }
  static I load(const std::uint32_t* p) { return {_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))}; }
  static I lane_index() { return {_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)}; }
  static void store(float* p, F a) { _mm256_storeu_ps(p, a.v); }
  static void store(std::int32_t* p, I a) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), a.v); }
  static std::uint32_t bits(M a) { return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(a.m))); }
  static M none() { return {_mm256_setzero_si256()}; }
  static M all() { return {_mm256_set1_epi32(-1)}; }
  /// Writes the lanes of `m` of `values` to dst[0 ..), in lane order (dst needs room for 8);
  /// returns how many it kept. Integer or float lanes. (A permute and a whole store: copied a lane
  /// at a time from the stack, they were ~45% of the sphere pass's samples, 1024 bunnies' AO on AMD EPYC.)
  static int compress(std::uint32_t* dst, I values, M m) {
    const std::uint32_t lanes = bits(m);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(dst), _mm256_permutevar8x32_epi32(values.v, simd::compress_index8(lanes)));
    return __builtin_popcount(lanes);
  }
  static int compress(float* dst, F values, M m) {
    const std::uint32_t lanes = bits(m);
    _mm256_storeu_ps(dst, _mm256_permutevar8x32_ps(values.v, simd::compress_index8(lanes)));
    return __builtin_popcount(lanes);
  }
  /// p[lane] = 1 for the lanes of `m`; the other bytes of p[0 .. 8) keep their values.
  static void set_bytes(std::uint8_t* p, M m) {
    for (std::uint32_t lanes = bits(m); lanes != 0; lanes &= lanes - 1) p[__builtin_ctz(lanes)] = 1;
  }
  /// The 8 columns of 8 consecutive rows of 8 floats at `p` (column c, lane l = p[8l + c]).
  static void transpose_rows(const float* p, F column[8]) {
    __m256 c[8];
    simd::rows_to_columns8(p, c);
    for (int k = 0; k < 8; ++k) column[k].v = c[k];
  }
  /// The 8 columns of the rows of 8 floats at base + 8·index[l], l < 8: the rows loaded and
  /// transposed (a gather a column made the corner's cow spend 31% of its field time here, AMD EPYC).
  static void transpose_rows_at(const float* base, const std::uint32_t* index, F column[8]) {
    __m256 c[8];
    simd::rows_to_columns8(base, index, c);
    for (int k = 0; k < 8; ++k) column[k].v = c[k];
  }
};

inline Avx2::M operator&(Avx2::M a, Avx2::M b) { return {_mm256_and_si256(a.m, b.m)}; }
inline Avx2::M operator|(Avx2::M a, Avx2::M b) { return {_mm256_or_si256(a.m, b.m)}; }
inline Avx2::M operator~(Avx2::M a) { return {_mm256_xor_si256(a.m, _mm256_set1_epi32(-1))}; }
inline Avx2::M operator^(Avx2::M a, Avx2::M b) { return {_mm256_xor_si256(a.m, b.m)}; }
inline bool any(Avx2::M a) { return !_mm256_testz_si256(a.m, a.m); }

inline Avx2::F operator+(Avx2::F a, Avx2::F b) { return {_mm256_add_ps(a.v, b.v)}; }
inline Avx2::F operator-(Avx2::F a, Avx2::F b) { return {_mm256_sub_ps(a.v, b.v)}; }
inline Avx2::F operator*(Avx2::F a, Avx2::F b) { return {_mm256_mul_ps(a.v, b.v)}; }
inline Avx2::F operator/(Avx2::F a, Avx2::F b) { return {_mm256_div_ps(a.v, b.v)}; }
inline Avx2::F operator-(Avx2::F a) { return {_mm256_xor_ps(a.v, _mm256_set1_ps(-0.0f))}; }
inline Avx2::M float_mask(__m256 m) { return {_mm256_castps_si256(m)}; }
inline Avx2::M operator<(Avx2::F a, Avx2::F b) { return float_mask(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)); }
inline Avx2::M operator<=(Avx2::F a, Avx2::F b) { return float_mask(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)); }
inline Avx2::M operator>(Avx2::F a, Avx2::F b) { return float_mask(_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)); }
inline Avx2::M operator>=(Avx2::F a, Avx2::F b) { return float_mask(_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)); }
inline Avx2::M operator==(Avx2::F a, Avx2::F b) { return float_mask(_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)); }
inline Avx2::F sqrt(Avx2::F a) { return {_mm256_sqrt_ps(a.v)}; }
/// a·b + c rounded once (hd::fma).
inline Avx2::F fma(Avx2::F a, Avx2::F b, Avx2::F c) { return {_mm256_fmadd_ps(a.v, b.v, c.v)}; }
inline Avx2::F abs(Avx2::F a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
inline Avx2::F floor(Avx2::F a) { return {_mm256_floor_ps(a.v)}; }
/// a > b ? a : b (b when either is NaN).
inline Avx2::F max(Avx2::F a, Avx2::F b) { return {_mm256_max_ps(a.v, b.v)}; }
/// a < b ? a : b (b when either is NaN).
inline Avx2::F min(Avx2::F a, Avx2::F b) { return {_mm256_min_ps(a.v, b.v)}; }
/// |magnitude| with the sign bit of `sign`.
inline Avx2::F copysign(Avx2::F magnitude, Avx2::F sign) {
  const __m256 bit = _mm256_set1_ps(-0.0f);
  return {_mm256_or_ps(_mm256_andnot_ps(bit, magnitude.v), _mm256_and_ps(bit, sign.v))};
}
#if defined(__AVX512VL__)
// GCC 12 with AVX-512VL folds a negated mask (~m) into vpblendvb by dropping the negation, so
// select(~m, a, b) came out as select(m, a, b); the and/andnot/or form (one vpternlog) is immune.
inline Avx2::F select(Avx2::M m, Avx2::F a, Avx2::F b) {
  const __m256 mask = _mm256_castsi256_ps(m.m);
  return {_mm256_or_ps(_mm256_and_ps(mask, a.v), _mm256_andnot_ps(mask, b.v))};
}
inline Avx2::I select(Avx2::M m, Avx2::I a, Avx2::I b) { return {_mm256_or_si256(_mm256_and_si256(m.m, a.v), _mm256_andnot_si256(m.m, b.v))}; }
#else
inline Avx2::F select(Avx2::M m, Avx2::F a, Avx2::F b) { return {_mm256_blendv_ps(b.v, a.v, _mm256_castsi256_ps(m.m))}; }
inline Avx2::I select(Avx2::M m, Avx2::I a, Avx2::I b) { return {_mm256_blendv_epi8(b.v, a.v, m.m)}; }
#endif
/// Truncation towards zero (C's float-to-int conversion).
inline Avx2::I to_int(Avx2::F a) { return {_mm256_cvttps_epi32(a.v)}; }
inline Avx2::F to_float(Avx2::I a) { return {_mm256_cvtepi32_ps(a.v)}; }

inline Avx2::I operator+(Avx2::I a, Avx2::I b) { return {_mm256_add_epi32(a.v, b.v)}; }
inline Avx2::I operator-(Avx2::I a, Avx2::I b) { return {_mm256_sub_epi32(a.v, b.v)}; }
inline Avx2::I operator*(Avx2::I a, Avx2::I b) { return {_mm256_mullo_epi32(a.v, b.v)}; }
inline Avx2::I operator&(Avx2::I a, Avx2::I b) { return {_mm256_and_si256(a.v, b.v)}; }
inline Avx2::I operator|(Avx2::I a, Avx2::I b) { return {_mm256_or_si256(a.v, b.v)}; }
inline Avx2::I operator<<(Avx2::I a, Avx2::I b) { return {_mm256_sllv_epi32(a.v, b.v)}; }
inline Avx2::I operator>>(Avx2::I a, Avx2::I b) { return {_mm256_srlv_epi32(a.v, b.v)}; }
inline Avx2::M operator<(Avx2::I a, Avx2::I b) { return {_mm256_cmpgt_epi32(b.v, a.v)}; }
inline Avx2::M operator<=(Avx2::I a, Avx2::I b) { return ~Avx2::M{_mm256_cmpgt_epi32(a.v, b.v)}; }
inline Avx2::M operator==(Avx2::I a, Avx2::I b) { return {_mm256_cmpeq_epi32(a.v, b.v)}; }
inline Avx2::I min(Avx2::I a, Avx2::I b) { return {_mm256_min_epi32(a.v, b.v)}; }
inline Avx2::I max(Avx2::I a, Avx2::I b) { return {_mm256_max_epi32(a.v, b.v)}; }
inline Avx2::I abs(Avx2::I a) { return {_mm256_abs_epi32(a.v)}; }

/// base[index] for the lanes of `m`, 0 elsewhere.
inline Avx2::F gather(const float* base, Avx2::I index, Avx2::M m) {
  return {_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, index.v, _mm256_castsi256_ps(m.m), 4)};
}
/// The 32 bits at byte offset `offset` from `base` for the lanes of `m`, 0 elsewhere.
inline Avx2::I gather_bytes(const void* base, Avx2::I offset, Avx2::M m) {
  return {_mm256_mask_i32gather_epi32(_mm256_setzero_si256(), static_cast<const int*>(base), offset.v, m.m, 1)};
}
/// The two floats of table[index] (64 bits each; every lane's index valid): the low one into
/// `first`, the high one into `second` (two 4-lane 64-bit gathers, then shuffles).
inline void gather_pairs(const unsigned long long* table, Avx2::I index, Avx2::F& first, Avx2::F& second) {
  const auto* base = reinterpret_cast<const long long*>(table);
  const __m256 lo = _mm256_castsi256_ps(_mm256_i32gather_epi64(base, _mm256_castsi256_si128(index.v), 8));
  const __m256 hi = _mm256_castsi256_ps(_mm256_i32gather_epi64(base, _mm256_extracti128_si256(index.v, 1), 8));
  // Per 128-bit half [lo.a, lo.b, hi.a, hi.b], then the 64-bit quarters put back in lane order.
  first.v = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(lo, hi, 0x88)), 0xD8));
  second.v = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(lo, hi, 0xDD)), 0xD8));
}
#endif

/// Two packets of a backend L side by side (2·L::kWidth lanes): every operation is L's on the first
/// half, then on the second, so the two halves' independent chains interleave in the instruction
/// stream (the kernel's steps are long dependency chains; one packet leaves the core waiting on them).
template <class L>
struct PairM {
  typename L::M a, b;
};
template <class L>
struct PairF {
  typename L::F a, b;
};
template <class L>
struct PairI {
  typename L::I a, b;
};

template <class L>
struct Pair {
  static constexpr int kWidth = 2 * L::kWidth;
  static_assert(kWidth <= 32, "bits() holds a mask in 32 bits");
  using M = PairM<L>;
  using F = PairF<L>;
  using I = PairI<L>;
  static F splat(float x) { return {L::splat(x), L::splat(x)}; }
  static I splat(int x) { return {L::splat(x), L::splat(x)}; }
  static F load(const float* p) { return {L::load(p), L::load(p + L::kWidth)}; }
  static I load(const std::uint32_t* p) { return {L::load(p), L::load(p + L::kWidth)}; }
  static I lane_index() { return {L::lane_index(), L::lane_index() + L::splat(L::kWidth)}; }
  static void store(float* p, F x) { L::store(p, x.a), L::store(p + L::kWidth, x.b); }
  static void store(std::int32_t* p, I x) { L::store(p, x.a), L::store(p + L::kWidth, x.b); }
  static std::uint32_t bits(M x) { return L::bits(x.a) | (L::bits(x.b) << L::kWidth); }
  static M none() { return {L::none(), L::none()}; }
  static M all() { return {L::all(), L::all()}; }
  static int compress(std::uint32_t* dst, I values, M m) {
    const int n = L::compress(dst, values.a, m.a);
    return n + L::compress(dst + n, values.b, m.b);
  }
  static int compress(float* dst, F values, M m) {
    const int n = L::compress(dst, values.a, m.a);
    return n + L::compress(dst + n, values.b, m.b);
  }
  static void set_bytes(std::uint8_t* p, M m) { L::set_bytes(p, m.a), L::set_bytes(p + L::kWidth, m.b); }
  static void transpose_rows(const float* p, F column[8]) {
    typename L::F first[8], second[8];
    L::transpose_rows(p, first);
    L::transpose_rows(p + 8 * L::kWidth, second);
    for (int k = 0; k < 8; ++k) column[k] = {first[k], second[k]};
  }
  static void transpose_rows_at(const float* base, const std::uint32_t* index, F column[8]) {
    typename L::F first[8], second[8];
    L::transpose_rows_at(base, index, first);
    L::transpose_rows_at(base, index + L::kWidth, second);
    for (int k = 0; k < 8; ++k) column[k] = {first[k], second[k]};
  }
};

template <class L> PairM<L> operator&(PairM<L> x, PairM<L> y) { return {x.a & y.a, x.b & y.b}; }
template <class L> PairM<L> operator|(PairM<L> x, PairM<L> y) { return {x.a | y.a, x.b | y.b}; }
template <class L> PairM<L> operator^(PairM<L> x, PairM<L> y) { return {x.a ^ y.a, x.b ^ y.b}; }
template <class L> PairM<L> operator~(PairM<L> x) { return {~x.a, ~x.b}; }
template <class L> bool any(PairM<L> x) { return any(x.a | x.b); }

template <class L> PairF<L> operator+(PairF<L> x, PairF<L> y) { return {x.a + y.a, x.b + y.b}; }
template <class L> PairF<L> operator-(PairF<L> x, PairF<L> y) { return {x.a - y.a, x.b - y.b}; }
template <class L> PairF<L> operator*(PairF<L> x, PairF<L> y) { return {x.a * y.a, x.b * y.b}; }
template <class L> PairF<L> operator/(PairF<L> x, PairF<L> y) { return {x.a / y.a, x.b / y.b}; }
template <class L> PairF<L> operator-(PairF<L> x) { return {-x.a, -x.b}; }
template <class L> PairM<L> operator<(PairF<L> x, PairF<L> y) { return {x.a < y.a, x.b < y.b}; }
template <class L> PairM<L> operator<=(PairF<L> x, PairF<L> y) { return {x.a <= y.a, x.b <= y.b}; }
template <class L> PairM<L> operator>(PairF<L> x, PairF<L> y) { return {x.a > y.a, x.b > y.b}; }
template <class L> PairM<L> operator>=(PairF<L> x, PairF<L> y) { return {x.a >= y.a, x.b >= y.b}; }
template <class L> PairM<L> operator==(PairF<L> x, PairF<L> y) { return {x.a == y.a, x.b == y.b}; }
template <class L> PairF<L> sqrt(PairF<L> x) { return {sqrt(x.a), sqrt(x.b)}; }
template <class L> PairF<L> fma(PairF<L> x, PairF<L> y, PairF<L> z) { return {fma(x.a, y.a, z.a), fma(x.b, y.b, z.b)}; }
template <class L> PairF<L> abs(PairF<L> x) { return {abs(x.a), abs(x.b)}; }
template <class L> PairF<L> floor(PairF<L> x) { return {floor(x.a), floor(x.b)}; }
template <class L> PairF<L> max(PairF<L> x, PairF<L> y) { return {max(x.a, y.a), max(x.b, y.b)}; }
template <class L> PairF<L> min(PairF<L> x, PairF<L> y) { return {min(x.a, y.a), min(x.b, y.b)}; }
template <class L> PairF<L> copysign(PairF<L> x, PairF<L> y) { return {copysign(x.a, y.a), copysign(x.b, y.b)}; }
template <class L> PairF<L> select(PairM<L> m, PairF<L> x, PairF<L> y) { return {select(m.a, x.a, y.a), select(m.b, x.b, y.b)}; }
template <class L> PairI<L> select(PairM<L> m, PairI<L> x, PairI<L> y) { return {select(m.a, x.a, y.a), select(m.b, x.b, y.b)}; }
template <class L> PairI<L> to_int(PairF<L> x) { return {to_int(x.a), to_int(x.b)}; }
template <class L> PairF<L> to_float(PairI<L> x) { return {to_float(x.a), to_float(x.b)}; }

template <class L> PairI<L> operator+(PairI<L> x, PairI<L> y) { return {x.a + y.a, x.b + y.b}; }
template <class L> PairI<L> operator-(PairI<L> x, PairI<L> y) { return {x.a - y.a, x.b - y.b}; }
template <class L> PairI<L> operator*(PairI<L> x, PairI<L> y) { return {x.a * y.a, x.b * y.b}; }
template <class L> PairI<L> operator&(PairI<L> x, PairI<L> y) { return {x.a & y.a, x.b & y.b}; }
template <class L> PairI<L> operator|(PairI<L> x, PairI<L> y) { return {x.a | y.a, x.b | y.b}; }
template <class L> PairI<L> operator<<(PairI<L> x, PairI<L> y) { return {x.a << y.a, x.b << y.b}; }
template <class L> PairI<L> operator>>(PairI<L> x, PairI<L> y) { return {x.a >> y.a, x.b >> y.b}; }
template <class L> PairM<L> operator<(PairI<L> x, PairI<L> y) { return {x.a < y.a, x.b < y.b}; }
template <class L> PairM<L> operator<=(PairI<L> x, PairI<L> y) { return {x.a <= y.a, x.b <= y.b}; }
template <class L> PairM<L> operator==(PairI<L> x, PairI<L> y) { return {x.a == y.a, x.b == y.b}; }
template <class L> PairI<L> min(PairI<L> x, PairI<L> y) { return {min(x.a, y.a), min(x.b, y.b)}; }
template <class L> PairI<L> max(PairI<L> x, PairI<L> y) { return {max(x.a, y.a), max(x.b, y.b)}; }
template <class L> PairI<L> abs(PairI<L> x) { return {abs(x.a), abs(x.b)}; }

template <class L> PairF<L> gather(const float* base, PairI<L> index, PairM<L> m) {
  return {gather(base, index.a, m.a), gather(base, index.b, m.b)};
}
template <class L> PairI<L> gather_bytes(const void* base, PairI<L> offset, PairM<L> m) {
  return {gather_bytes(base, offset.a, m.a), gather_bytes(base, offset.b, m.b)};
}
template <class L> void gather_pairs(const unsigned long long* table, PairI<L> index, PairF<L>& first, PairF<L>& second) {
  gather_pairs(table, index.a, first.a, second.a);
  gather_pairs(table, index.b, first.b, second.b);
}

}  // namespace vf::field::lanes
