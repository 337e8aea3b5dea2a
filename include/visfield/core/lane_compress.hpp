#pragma once
/// \file AVX2's stand-in for AVX-512's compress: the permute that moves a mask's lanes to the front,
/// in order (the box tree's columns walk, the field scene's rows on AVX2).

#include <array>
#include <cstdint>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace vf::simd {

#if defined(__AVX2__)
/// The numbers of the lanes set in the 8-bit mask `m` (bit i = lane i), in order, in the first lanes;
/// the lanes after them 0. Applied by _mm256_permutevar8x32_ps / _epi32, it compresses a register.
inline __m256i compress_index8(std::uint32_t m) {
  // kNibbles[m]: those lane numbers a nibble each, the first in the lowest: 1 KiB against 8 for a
  // table of whole registers.
  static constexpr std::array<std::uint32_t, 256> kNibbles = [] {
    std::array<std::uint32_t, 256> table{};
    for (unsigned mask = 0; mask < 256; ++mask) {
      int at = 0;
      for (unsigned lane = 0; lane < 8; ++lane)
        if ((mask >> lane) & 1u) table[mask] |= lane << (4 * at++);
    }
    return table;
  }();
  const __m256i nibbles = _mm256_srlv_epi32(_mm256_set1_epi32(static_cast<int>(kNibbles[m & 0xffu])), _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28));
  return _mm256_and_si256(nibbles, _mm256_set1_epi32(15));
}
#endif

}  // namespace vf::simd
