#pragma once
/// \file Rows of 8 floats (a Ray: origin, direction, tmin, tmax) turned into 8 columns of SIMD lanes,
/// in registers: how the batch kernels read consecutive rays (and, on AVX2, rays by index) without
/// gathering them (the field kernel, a field scene's blocks, the box tree's setup).

#include <cstddef>
#include <cstdint>

#if defined(__AVX2__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace vf::simd {

#if defined(__AVX512F__)
/// The 8 columns of the 16 consecutive rows of 8 floats at `p` (column c, lane l = p[8l + c]): per
/// 128-bit block unpacks and shuffles, then one two-source permute a column; cheaper than 8 gathers.
inline void rows_to_columns16(const float* p, __m512 column[8]) {
  // The zero-masking forms with every lane kept: GCC 12's plain forms trip its own
  // uninitialised-value warning (measured level with them: 9 bunnies' AO, six interleaved rounds).
  constexpr __mmask16 all = 0xffff;
  // The rows loaded where the first step takes them: loaded into an array first, GCC made the loads
  // a memcpy call onto the stack (its loop distribution).
  __m512 t[8], u[8];
  for (int k = 0; k < 8; k += 2) {
    const __m512 a = _mm512_loadu_ps(p + 16 * k), b = _mm512_loadu_ps(p + 16 * (k + 1));
    t[k] = _mm512_maskz_unpacklo_ps(all, a, b);
    t[k + 1] = _mm512_maskz_unpackhi_ps(all, a, b);
  }
  for (int h = 0; h < 8; h += 4) {
    u[h] = _mm512_maskz_shuffle_ps(all, t[h], t[h + 2], 0x44);
    u[h + 1] = _mm512_maskz_shuffle_ps(all, t[h], t[h + 2], 0xEE);
    u[h + 2] = _mm512_maskz_shuffle_ps(all, t[h + 1], t[h + 3], 0x44);
    u[h + 3] = _mm512_maskz_shuffle_ps(all, t[h + 1], t[h + 3], 0xEE);
  }
  // u[c] (c < 4) holds column c in its 128-bit blocks 0 (rows 0, 2, 4, 6) and 2 (rows 1, 3, 5, 7)
  // and column c + 4 in blocks 1 and 3; u[c + 4] the same for rows 8..15.
  const __m512i low = _mm512_setr_epi32(0, 8, 1, 9, 2, 10, 3, 11, 16, 24, 17, 25, 18, 26, 19, 27);
  const __m512i high = _mm512_setr_epi32(4, 12, 5, 13, 6, 14, 7, 15, 20, 28, 21, 29, 22, 30, 23, 31);
  for (int c = 0; c < 4; ++c) {
    column[c] = _mm512_maskz_permutex2var_ps(all, u[c], low, u[c + 4]);
    column[c + 4] = _mm512_maskz_permutex2var_ps(all, u[c], high, u[c + 4]);
  }
}
#endif

#if defined(__AVX2__)
/// The 8 columns of the 8 rows row(0) .. row(7) of 8 floats (column c, lane l = row(l)[c]): the
/// classic 8×8 in-register transpose. The rows are taken where the first step needs them: loaded
/// into an array first, GCC made the loads a memcpy call onto the stack (its loop distribution).
template <class Row>
[[gnu::always_inline]] inline void rows_to_columns8_of(const Row& row, __m256 column[8]) {
  __m256 t[8], u[8];
  for (int k = 0; k < 8; k += 2) {
    const __m256 a = row(k), b = row(k + 1);
    t[k] = _mm256_unpacklo_ps(a, b);
    t[k + 1] = _mm256_unpackhi_ps(a, b);
  }
  for (int h = 0; h < 8; h += 4) {
    u[h] = _mm256_shuffle_ps(t[h], t[h + 2], 0x44);
    u[h + 1] = _mm256_shuffle_ps(t[h], t[h + 2], 0xEE);
    u[h + 2] = _mm256_shuffle_ps(t[h + 1], t[h + 3], 0x44);
    u[h + 3] = _mm256_shuffle_ps(t[h + 1], t[h + 3], 0xEE);
  }
  for (int c = 0; c < 4; ++c) {
    column[c] = _mm256_permute2f128_ps(u[c], u[c + 4], 0x20);
    column[c + 4] = _mm256_permute2f128_ps(u[c], u[c + 4], 0x31);
  }
}

/// The 8 columns of 8 rows of 8 floats held in registers (column c, lane l = a[l][c]).
inline void rows_to_columns8(const __m256 a[8], __m256 column[8]) {
  rows_to_columns8_of([&](int k) { return a[k]; }, column);
}

/// The 8 columns of the 8 consecutive rows of 8 floats at `p` (column c, lane l = p[8l + c]).
inline void rows_to_columns8(const float* p, __m256 column[8]) {
  rows_to_columns8_of([&](int k) { return _mm256_loadu_ps(p + 8 * k); }, column);
}

/// The 8 columns of the rows of 8 floats at base + 8·index[l], l < 8 (column c, lane l =
/// base[8·index[l] + c]): eight row loads and the transpose, in place of eight 8-lane gathers.
inline void rows_to_columns8(const float* base, const std::uint32_t* index, __m256 column[8]) {
  rows_to_columns8_of([&](int k) { return _mm256_loadu_ps(base + 8 * static_cast<std::size_t>(index[k])); }, column);
}
#endif

}  // namespace vf::simd
