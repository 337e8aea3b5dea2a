#pragma once
/// \file Drawing samples on lanes — 16 on AVX-512 (F and DQ), 8 on AVX2 — with the very bits of the
/// scalar samplers: a PCG stream handed out two numbers per lane (the numbers 2l and 2l + 1 of a
/// packet go to lane l, as a loop drawing two per sample takes them), and hd::quadrant_sincos's
/// polynomials on lanes. Used by ao_rays() and SphereCone::sample(Rng&, ...). VF_SAMPLE_LANES is
/// defined where the build has lanes; without them the header is empty and the callers draw one
/// sample at a time.

#if (defined(__AVX512F__) && defined(__AVX512DQ__)) || defined(__AVX2__)
#define VF_SAMPLE_LANES 1
#include <immintrin.h>

#include <cstdint>

#include "visfield/core/host_device.hpp"
#include "visfield/core/lane_compress.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/row_transpose.hpp"

namespace vf::render_detail {

/// M^(2l) and M^(2l-1) + ... + 1 for l = 0 .. 23 (M the PCG multiplier; l = 16: a packet's 32 numbers).
struct PcgSteps {
  alignas(64) long long power[24];
  alignas(64) long long sum[24];
};
constexpr PcgSteps pcg_steps() {
  PcgSteps t{};
  std::uint64_t power = 1, sum = 0;
  for (int l = 0; l < 24; ++l) {
    t.power[l] = static_cast<long long>(power);
    t.sum[l] = static_cast<long long>(sum);
    for (int k = 0; k < 2; ++k) {
      sum += power;
      power *= Rng::kMultiplier;
    }
  }
  return t;
}
inline constexpr PcgSteps kPcgSteps = pcg_steps();

#if defined(__AVX512F__) && defined(__AVX512DQ__)
/// The samplers' operations on 16 AVX-512 lanes; masks are bit masks.
struct SampleLanes {
  static constexpr int kWidth = 16;
  using F = __m512;
  using I = __m512i;
  using M = __mmask16;
  static F splat(float x) { return _mm512_set1_ps(x); }
  static F add(F a, F b) { return _mm512_add_ps(a, b); }
  static F sub(F a, F b) { return _mm512_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm512_mul_ps(a, b); }
  static F div(F a, F b) { return _mm512_div_ps(a, b); }
  static F sqrt(F a) { return _mm512_sqrt_ps(a); }
  static F min(F a, F b) { return _mm512_min_ps(a, b); }
  static F max(F a, F b) { return _mm512_max_ps(a, b); }
  static F abs(F a) { return _mm512_abs_ps(a); }
  static F floor(F a) { return _mm512_roundscale_ps(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
  /// The magnitude of `magnitude` with the sign of `sign`.
  static F copysign(F magnitude, F sign) {
    const F bit = splat(-0.0f);
    return _mm512_or_ps(_mm512_andnot_ps(bit, magnitude), _mm512_and_ps(bit, sign));
  }
  static M equal(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
  static M greater_equal(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ); }
  static M less(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
  static M both(M a, M b) { return a & b; }
  /// `if_set` in the lanes of m, `otherwise` elsewhere.
  static F blend(M m, F otherwise, F if_set) { return _mm512_mask_blend_ps(m, otherwise, if_set); }
  /// x with its sign flipped in the lanes of m.
  static F negate_where(M m, F x) { return _mm512_mask_xor_ps(x, m, x, splat(-0.0f)); }
  /// x truncated to integer lanes.
  static I truncate(F x) { return _mm512_cvttps_epi32(x); }
  static I add(I a, int k) { return _mm512_add_epi32(a, _mm512_set1_epi32(k)); }
  /// The lanes of q with bit `bit` (a power of two) set.
  static M has_bit(I q, int bit) { return _mm512_test_epi32_mask(q, _mm512_set1_epi32(bit)); }
  static M at_least(I q, int k) { return _mm512_cmpge_epi32_mask(q, _mm512_set1_epi32(k)); }
  static void store(float* p, F x) { _mm512_store_ps(p, x); }
  static F load(const float* p) { return _mm512_load_ps(p); }
  static I load(const std::int32_t* p) { return _mm512_load_si512(p); }
  /// table[index] in each lane (a table of kWidth floats, 64-byte aligned; every index < kWidth).
  static F lookup(const float* table, I index) { return _mm512_permutexvar_ps(index, _mm512_load_ps(table)); }
  /// `first` in the lanes below `boundary`, first + 1 in the others.
  static I step_at(int first, int boundary) {
    const I iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15), base = _mm512_set1_epi32(first);
    return _mm512_mask_add_epi32(base, _mm512_cmpge_epi32_mask(iota, _mm512_set1_epi32(boundary)), base, _mm512_set1_epi32(1));
  }
  /// The lanes whose bit is set in `bits`.
  static M from_bits(std::uint32_t bits) { return static_cast<M>(bits); }
  static std::uint32_t bits(M m) { return m; }
  /// x's lanes of m, in order, in the first lanes (the others unspecified).
  static F compress(F x, M m) { return _mm512_maskz_compress_ps(m, x); }
  /// kWidth rays from columns (origin x, y, z, direction x, y, z, tmin, tmax) to out[0 .. kWidth): two 8×8 transposes.
  static void store_rays(Ray* out, const F column[8]) {
    for (int half = 0; half < 2; ++half) {
      __m256 c[8], row[8];
      for (int k = 0; k < 8; ++k) c[k] = half == 0 ? _mm512_castps512_ps256(column[k]) : _mm512_extractf32x8_ps(column[k], 1);
      simd::rows_to_columns8(c, row);  // an 8×8 transpose is its own inverse
      for (int k = 0; k < 8; ++k) _mm256_storeu_ps(reinterpret_cast<float*>(out + 8 * half + k), row[k]);
    }
  }
};

/// A stream's numbers two per lane, 16 lanes a packet: pairs() gives the packet's (first, second)
/// of every lane and steps on. After k packets the caller's Rng moves on by rng.advanced(32 k).
class PairLanes {
 public:
  /// Lanes starting at `rng`'s next number.
  explicit PairLanes(const Rng& rng) : increment_(rng.increment()) {
    // n steps map s to M^n s + inc (M^(n-1) + ... + 1): the powers and sums are tables, so lane l's
    // start (n = 2l) and the packets' jump (n = 32) cost a multiply-add each.
    const __m512i inc = _mm512_set1_epi64(static_cast<long long>(increment_)), start = _mm512_set1_epi64(static_cast<long long>(rng.state()));
    const auto stepped = [&](int first_lane) {
      return _mm512_add_epi64(_mm512_mullo_epi64(_mm512_load_si512(kPcgSteps.power + first_lane), start),
                              _mm512_mullo_epi64(_mm512_load_si512(kPcgSteps.sum + first_lane), inc));
    };
    low_ = stepped(0);
    high_ = stepped(8);
    jump_mult_ = _mm512_set1_epi64(kPcgSteps.power[16]);
    jump_add_ = _mm512_mullo_epi64(_mm512_set1_epi64(kPcgSteps.sum[16]), inc);
  }
  /// The next packet: each lane's two uniform() numbers, then the lanes step 32 numbers on.
  void pairs(__m512& first, __m512& second) {
    const __m512i mult = _mm512_set1_epi64(static_cast<long long>(Rng::kMultiplier));
    const __m512i add = _mm512_set1_epi64(static_cast<long long>(increment_));
    const auto next = [&](__m512i state) { return _mm512_add_epi64(_mm512_mullo_epi64(state, mult), add); };
    first = _mm512_insertf32x8(_mm512_castps256_ps512(uniforms(low_)), uniforms(high_), 1);
    second = _mm512_insertf32x8(_mm512_castps256_ps512(uniforms(next(low_))), uniforms(next(high_)), 1);
    low_ = _mm512_add_epi64(_mm512_mullo_epi64(low_, jump_mult_), jump_add_);
    high_ = _mm512_add_epi64(_mm512_mullo_epi64(high_, jump_mult_), jump_add_);
  }

 private:
  /// Floats of the 8 states in `state` turned into uniform() numbers (next_u32's output, >> 8, × 2^-24).
  static __m256 uniforms(__m512i state) {
    const __m512i xorshifted = _mm512_srli_epi64(_mm512_xor_si512(_mm512_srli_epi64(state, 18), state), 27);
    const __m256i rot = _mm512_cvtepi64_epi32(_mm512_srli_epi64(state, 59));
    const __m256i low = _mm512_cvtepi64_epi32(xorshifted);  // the low 32 bits, as the cast keeps them
    const __m256i word = _mm256_or_si256(_mm256_srlv_epi32(low, rot),
                                         _mm256_sllv_epi32(low, _mm256_and_si256(_mm256_sub_epi32(_mm256_set1_epi32(32), rot), _mm256_set1_epi32(31))));
    return _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(word, 8)), _mm256_set1_ps(0x1p-24f));
  }

  std::uint64_t increment_;
  __m512i low_, high_, jump_mult_, jump_add_;
};
#else
/// SampleLanes' operations on 8 AVX2 lanes; masks are lanes of all ones or all zeros.
struct SampleLanes {
  static constexpr int kWidth = 8;
  using F = __m256;
  using I = __m256i;
  using M = __m256;
  static F splat(float x) { return _mm256_set1_ps(x); }
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F div(F a, F b) { return _mm256_div_ps(a, b); }
  static F sqrt(F a) { return _mm256_sqrt_ps(a); }
  static F min(F a, F b) { return _mm256_min_ps(a, b); }
  static F max(F a, F b) { return _mm256_max_ps(a, b); }
  static F abs(F a) { return _mm256_andnot_ps(splat(-0.0f), a); }
  static F floor(F a) { return _mm256_floor_ps(a); }
  static F copysign(F magnitude, F sign) {
    const F bit = splat(-0.0f);
    return _mm256_or_ps(_mm256_andnot_ps(bit, magnitude), _mm256_and_ps(bit, sign));
  }
  static M equal(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
  static M greater_equal(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
  static M less(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  static M both(M a, M b) { return _mm256_and_ps(a, b); }
  static F blend(M m, F otherwise, F if_set) { return _mm256_blendv_ps(otherwise, if_set, m); }
  static F negate_where(M m, F x) { return _mm256_xor_ps(x, _mm256_and_ps(m, splat(-0.0f))); }
  static I truncate(F x) { return _mm256_cvttps_epi32(x); }
  static I add(I a, int k) { return _mm256_add_epi32(a, _mm256_set1_epi32(k)); }
  static M has_bit(I q, int bit) {
    const __m256i b = _mm256_set1_epi32(bit);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(q, b), b));
  }
  static M at_least(I q, int k) { return _mm256_castsi256_ps(_mm256_cmpgt_epi32(q, _mm256_set1_epi32(k - 1))); }
  static void store(float* p, F x) { _mm256_store_ps(p, x); }
  static F load(const float* p) { return _mm256_load_ps(p); }
  static I load(const std::int32_t* p) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(p)); }
  static F lookup(const float* table, I index) { return _mm256_permutevar8x32_ps(_mm256_load_ps(table), index); }
  static I step_at(int first, int boundary) {
    const __m256i past = _mm256_cmpgt_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_epi32(boundary - 1));
    return _mm256_sub_epi32(_mm256_set1_epi32(first), past);  // past lanes are -1
  }
  static M from_bits(std::uint32_t bits) {
    const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(bits)), lane_bit), lane_bit));
  }
  static std::uint32_t bits(M m) { return static_cast<std::uint32_t>(_mm256_movemask_ps(m)); }
  static F compress(F x, M m) { return _mm256_permutevar8x32_ps(x, simd::compress_index8(bits(m))); }
  static void store_rays(Ray* out, const F column[8]) {
    __m256 row[8];
    simd::rows_to_columns8(column, row);  // an 8×8 transpose is its own inverse
    for (int k = 0; k < 8; ++k) _mm256_storeu_ps(reinterpret_cast<float*>(out + k), row[k]);
  }
};

/// PairLanes on 8 AVX2 lanes: each lane's two numbers a packet, the lanes' 64-bit states four to a
/// register (AVX2 has no 64-bit multiply: three 32-bit ones make its low 64 bits).
class PairLanes {
 public:
  explicit PairLanes(const Rng& rng) : increment_(rng.increment()) {
    const __m256i inc = _mm256_set1_epi64x(static_cast<long long>(increment_)), start = _mm256_set1_epi64x(static_cast<long long>(rng.state()));
    const auto stepped = [&](int first_lane) {
      return _mm256_add_epi64(multiply(load(kPcgSteps.power + first_lane), start), multiply(load(kPcgSteps.sum + first_lane), inc));
    };
    low_ = stepped(0);
    high_ = stepped(4);
    jump_mult_ = _mm256_set1_epi64x(kPcgSteps.power[8]);
    jump_add_ = multiply(_mm256_set1_epi64x(kPcgSteps.sum[8]), inc);
  }
  /// The next packet: each lane's two uniform() numbers, then the lanes step 16 numbers on.
  void pairs(__m256& first, __m256& second) {
    const __m256i mult = _mm256_set1_epi64x(static_cast<long long>(Rng::kMultiplier));
    const __m256i mult_high = _mm256_set1_epi64x(static_cast<long long>(Rng::kMultiplier >> 32));
    const __m256i add = _mm256_set1_epi64x(static_cast<long long>(increment_));
    const auto next = [&](__m256i state) { return _mm256_add_epi64(multiply(state, mult, mult_high), add); };
    first = uniforms(low_, high_);
    second = uniforms(next(low_), next(high_));
    const __m256i jump_high = _mm256_srli_epi64(jump_mult_, 32);
    low_ = _mm256_add_epi64(multiply(low_, jump_mult_, jump_high), jump_add_);
    high_ = _mm256_add_epi64(multiply(high_, jump_mult_, jump_high), jump_add_);
  }

 private:
  static __m256i load(const long long* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
  /// The low 64 bits of a × b in each 64-bit lane, b_high = b >> 32: lo·lo + ((hi·lo + lo·hi) << 32).
  static __m256i multiply(__m256i a, __m256i b, __m256i b_high) {
    const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), b), _mm256_mul_epu32(a, b_high));
    return _mm256_add_epi64(_mm256_mul_epu32(a, b), _mm256_slli_epi64(cross, 32));
  }
  static __m256i multiply(__m256i a, __m256i b) { return multiply(a, b, _mm256_srli_epi64(b, 32)); }
  /// The uniform() numbers (next_u32's output, >> 8, × 2^-24) of the 4 states in `a` (lanes 0-3)
  /// and the 4 in `b` (lanes 4-7).
  static __m256 uniforms(__m256i a, __m256i b) {
    // next_u32's 32-bit rotation as a 64-bit shift: each lane's low output word copied into its high
    // half, shifted right by rot, leaves the rotated word in the low half.
    const auto rotated = [](__m256i state) {
      const __m256i xorshifted = _mm256_srli_epi64(_mm256_xor_si256(_mm256_srli_epi64(state, 18), state), 27);
      return _mm256_castsi256_ps(_mm256_srlv_epi64(_mm256_shuffle_epi32(xorshifted, 0xA0), _mm256_srli_epi64(state, 59)));
    };
    // The low words, per 128-bit half [a.., a.., b.., b..], then the 64-bit quarters put in lane order.
    const __m256 words = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(rotated(a), rotated(b), 0x88)), 0xD8));
    return _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(_mm256_castps_si256(words), 8)), _mm256_set1_ps(0x1p-24f));
  }

  std::uint64_t increment_;
  __m256i low_, high_, jump_mult_, jump_add_;
};
#endif

/// hd::quadrant_sincos on lanes: the same polynomials, multiplies and adds in the same order.
inline void quadrant_sincos(SampleLanes::F phi, SampleLanes::F& s, SampleLanes::F& c) {
  using L = SampleLanes;
  const auto step = [](L::F p, L::F x2, float k) { return L::add(L::mul(p, x2), L::splat(k)); };
  const auto step_down = [](L::F p, L::F x2, float k) { return L::sub(L::mul(p, x2), L::splat(k)); };
  const L::F x2 = L::mul(phi, phi);
  L::F ps = L::splat(1.0f / 6227020800.0f);
  ps = step_down(ps, x2, 1.0f / 39916800.0f);
  ps = step(ps, x2, 1.0f / 362880.0f);
  ps = step_down(ps, x2, 1.0f / 5040.0f);
  ps = step(ps, x2, 1.0f / 120.0f);
  ps = step_down(ps, x2, 1.0f / 6.0f);
  ps = step(ps, x2, 1.0f);
  s = L::mul(phi, ps);
  L::F pc = L::splat(-1.0f / 87178291200.0f);
  pc = step(pc, x2, 1.0f / 479001600.0f);
  pc = step_down(pc, x2, 1.0f / 3628800.0f);
  pc = step(pc, x2, 1.0f / 40320.0f);
  pc = step_down(pc, x2, 1.0f / 720.0f);
  pc = step(pc, x2, 1.0f / 24.0f);
  pc = step_down(pc, x2, 0.5f);
  c = step(pc, x2, 1.0f);
}

/// sincos_turn (sin and cos of 2πv) on lanes: the same quadrant, reduction and signs.
inline void sincos_turn(SampleLanes::F v, SampleLanes::F& s, SampleLanes::F& c) {
  using L = SampleLanes;
  const L::F x = L::mul(L::splat(4.0f), v);
  L::F q = L::floor(x);
  q = L::min(L::max(q, L::splat(0.0f)), L::splat(3.0f));  // v in [0, 1): no NaN
  L::F sr, cr;
  quadrant_sincos(L::mul(L::sub(x, q), L::splat(hd::kPi<float> / 2.0f)), sr, cr);
  const L::I quadrant = L::truncate(q);
  const L::M odd = L::has_bit(quadrant, 1);
  const L::M sin_negative = L::at_least(quadrant, 2);             // quadrants 2, 3
  const L::M cos_negative = L::has_bit(L::add(quadrant, 1), 2);  // quadrants 1, 2
  s = L::negate_where(sin_negative, L::blend(odd, sr, cr));
  c = L::negate_where(cos_negative, L::blend(odd, cr, sr));
}

/// Cones on lanes, each lane its own: what SphereCone::sample(u, v) computes with.
struct ConeLanes {
  SampleLanes::F axis[3], tangent[3], bitangent[3];
  SampleLanes::F distance, radius2, distance2, one_minus_cos_max;  // radius2, distance2: radius·radius, distance·distance
};

/// SphereCone::sample(u, v) on lanes: its operations in its order (no fused multiply-adds), so each
/// lane's direction `wi` and distance are the bits sample() gives its cone.
inline void cone_sample(const ConeLanes& c, SampleLanes::F u, SampleLanes::F v, SampleLanes::F wi[3], SampleLanes::F& distance) {
  using L = SampleLanes;
  const L::F zero = L::splat(0.0f), one = L::splat(1.0f);
  const L::F cos_theta = L::sub(one, L::mul(u, c.one_minus_cos_max));
  const L::F sin2 = L::sub(one, L::mul(cos_theta, cos_theta));
  const L::F sin_theta = L::sqrt(L::max(sin2, zero));
  L::F sin_phi, cos_phi;
  sincos_turn(v, sin_phi, cos_phi);
  const L::F a = L::mul(sin_theta, cos_phi), b = L::mul(sin_theta, sin_phi);
  L::F w[3];
  for (int i = 0; i < 3; ++i) w[i] = L::add(L::add(L::mul(c.tangent[i], a), L::mul(c.bitangent[i], b)), L::mul(c.axis[i], cos_theta));
  const L::F inverse = L::div(one, L::sqrt(L::add(L::add(L::mul(w[0], w[0]), L::mul(w[1], w[1])), L::mul(w[2], w[2]))));
  for (int i = 0; i < 3; ++i) wi[i] = L::mul(w[i], inverse);
  // Entry point along wi: the nearer root of |from + t wi - c| = r.
  const L::F inside = L::sub(c.radius2, L::mul(c.distance2, sin2));
  distance = L::max(L::sub(L::mul(c.distance, cos_theta), L::sqrt(L::max(inside, zero))), zero);
}

}  // namespace vf::render_detail
#endif
