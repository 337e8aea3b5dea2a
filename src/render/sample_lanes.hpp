#pragma once
/// \file Drawing 16 samples at a time on AVX-512 lanes with the very bits of the scalar samplers: a
/// PCG stream handed out two numbers per lane (the numbers 2l and 2l + 1 of a packet go to lane l,
/// as a loop drawing two per sample takes them), and hd::quadrant_sincos's polynomials on lanes.
/// Used by ao_rays() and SphereCone::sample(Rng&, ...). Empty without AVX-512F and DQ.

#if defined(__AVX512F__) && defined(__AVX512DQ__)
#include <immintrin.h>

#include <cstdint>

#include "visfield/core/host_device.hpp"
#include "visfield/core/rng.hpp"

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
    jump_mult_ = _mm512_set1_epi64(static_cast<long long>(kPcgSteps.power[16]));
    jump_add_ = _mm512_mullo_epi64(_mm512_set1_epi64(static_cast<long long>(kPcgSteps.sum[16])), inc);
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

/// hd::quadrant_sincos on lanes: the same polynomials, multiplies and adds in the same order.
inline void quadrant_sincos(__m512 phi, __m512& s, __m512& c) {
  const auto step = [](__m512 p, __m512 x2, float k) { return _mm512_add_ps(_mm512_mul_ps(p, x2), _mm512_set1_ps(k)); };
  const __m512 x2 = _mm512_mul_ps(phi, phi);
  __m512 ps = _mm512_set1_ps(1.0f / 6227020800.0f);
  ps = _mm512_sub_ps(_mm512_mul_ps(ps, x2), _mm512_set1_ps(1.0f / 39916800.0f));
  ps = step(ps, x2, 1.0f / 362880.0f);
  ps = _mm512_sub_ps(_mm512_mul_ps(ps, x2), _mm512_set1_ps(1.0f / 5040.0f));
  ps = step(ps, x2, 1.0f / 120.0f);
  ps = _mm512_sub_ps(_mm512_mul_ps(ps, x2), _mm512_set1_ps(1.0f / 6.0f));
  ps = step(ps, x2, 1.0f);
  s = _mm512_mul_ps(phi, ps);
  __m512 pc = _mm512_set1_ps(-1.0f / 87178291200.0f);
  pc = step(pc, x2, 1.0f / 479001600.0f);
  pc = _mm512_sub_ps(_mm512_mul_ps(pc, x2), _mm512_set1_ps(1.0f / 3628800.0f));
  pc = step(pc, x2, 1.0f / 40320.0f);
  pc = _mm512_sub_ps(_mm512_mul_ps(pc, x2), _mm512_set1_ps(1.0f / 720.0f));
  pc = step(pc, x2, 1.0f / 24.0f);
  pc = _mm512_sub_ps(_mm512_mul_ps(pc, x2), _mm512_set1_ps(0.5f));
  c = step(pc, x2, 1.0f);
}

/// sincos_turn (sin and cos of 2πv) on lanes: the same quadrant, reduction and signs.
inline void sincos_turn(__m512 v, __m512& s, __m512& c) {
  const __m512 x = _mm512_mul_ps(_mm512_set1_ps(4.0f), v);
  __m512 q = _mm512_roundscale_ps(x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  q = _mm512_min_ps(_mm512_max_ps(q, _mm512_setzero_ps()), _mm512_set1_ps(3.0f));  // v in [0, 1): no NaN
  __m512 sr, cr;
  quadrant_sincos(_mm512_mul_ps(_mm512_sub_ps(x, q), _mm512_set1_ps(hd::kPi<float> / 2.0f)), sr, cr);
  const __m512i quadrant = _mm512_cvttps_epi32(q);
  const __mmask16 odd = _mm512_test_epi32_mask(quadrant, _mm512_set1_epi32(1));
  const __mmask16 sin_negative = _mm512_cmpge_epi32_mask(quadrant, _mm512_set1_epi32(2));              // quadrants 2, 3
  const __mmask16 cos_negative = _mm512_cmpeq_epi32_mask(_mm512_and_si512(_mm512_add_epi32(quadrant, _mm512_set1_epi32(1)), _mm512_set1_epi32(2)),
                                                          _mm512_set1_epi32(2));  // quadrants 1, 2
  const __m512 sign = _mm512_set1_ps(-0.0f);
  s = _mm512_mask_blend_ps(odd, sr, cr);
  c = _mm512_mask_blend_ps(odd, cr, sr);
  s = _mm512_mask_xor_ps(s, sin_negative, s, sign);
  c = _mm512_mask_xor_ps(c, cos_negative, c, sign);
}

}  // namespace vf::render_detail
#endif
