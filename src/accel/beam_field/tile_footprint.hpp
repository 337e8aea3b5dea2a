#pragma once
// Private to accel (BeamField): the footprint of a reference, its projection's bounding square
// inside the tile quantised to 1/256 of the tile per axis in one 32-bit word, stored beside the
// reference. A ray projects into a tile as a short segment (a point on the fast path), so a
// reference whose footprint misses the segment's box cannot be hit there and its triangle test is
// skipped. On bunny's AO rays along stored lines this removes about nine triangle tests in ten.
//
// Encoding: bytes (s_lo, 255 - s_hi, t_lo, 255 - t_hi) for a footprint, and (s_hi, 255 - s_lo,
// t_hi, 255 - t_lo) for a ray's box (a "key"); they overlap exactly when every byte of the footprint
// is <= the key's byte, so sixteen references are filtered by one byte-wise max and compare.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__AVX512BW__) || defined(__AVX2__)
#include <immintrin.h>
#endif

namespace vf::beam {

/// Quantised tile coordinate of u (in tiles, 0 = the tile's low border): floor(256 u) clamped to
/// [0, 255]. Monotonic in u, which is all that conservativeness needs.
inline std::uint32_t footprint_step(double u) {
  const double x = u * 256.0;
  if (!(x > 0.0)) return 0;
  if (x >= 255.0) return 255;
  return static_cast<std::uint32_t>(x);
}

/// The footprint word of a reference whose projection lies in [s_lo, s_hi] × [t_lo, t_hi] (tile
/// units, relative to the tile's low corner; may extend past the tile).
inline std::uint32_t footprint(double s_lo, double s_hi, double t_lo, double t_hi) {
  return footprint_step(s_lo) | (255u - footprint_step(s_hi)) << 8 | footprint_step(t_lo) << 16 |
         (255u - footprint_step(t_hi)) << 24;
}

/// The key of a ray whose points in this tile lie in [s_lo, s_hi] × [t_lo, t_hi] (tile units).
inline std::uint32_t footprint_key(double s_lo, double s_hi, double t_lo, double t_hi) {
  return footprint_step(s_hi) | (255u - footprint_step(s_lo)) << 8 | footprint_step(t_hi) << 16 |
         (255u - footprint_step(t_lo)) << 24;
}

/// True when footprint `box` overlaps the ray box encoded by `key`.
inline bool footprint_overlaps(std::uint32_t box, std::uint32_t key) {
  for (int shift = 0; shift < 32; shift += 8)
    if (((box >> shift) & 0xffu) > ((key >> shift) & 0xffu)) return false;
  return true;
}

/// The lanes l < W whose ray key keys[l] footprint `box` overlaps (bit l set): one footprint against
/// W rays, the transpose of for_each_overlapping. `keys` is aligned to 4 W bytes.
template <int W>
inline std::uint32_t overlapping_keys(std::uint32_t box, const std::uint32_t* keys) {
#if defined(__AVX512BW__)
  if constexpr (W == 16) {
    const __m512i k = _mm512_load_si512(keys);
    return _mm512_cmpeq_epi32_mask(_mm512_max_epu8(_mm512_set1_epi32(static_cast<int>(box)), k), k);
  }
#endif
#if defined(__AVX2__)
  if constexpr (W == 8) {
    const __m256i k = _mm256_load_si256(reinterpret_cast<const __m256i*>(keys));
    const __m256i same = _mm256_cmpeq_epi32(_mm256_max_epu8(_mm256_set1_epi32(static_cast<int>(box)), k), k);
    return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(same)));
  }
#endif
  std::uint32_t lanes = 0;
  for (int l = 0; l < W; ++l) lanes |= static_cast<std::uint32_t>(footprint_overlaps(box, keys[l])) << l;
  return lanes;
}

/// Calls visit(r) for every r in [begin, end), in increasing order, whose footprint boxes[r]
/// overlaps `key`; stops and returns true as soon as visit returns true. AVX-512 (16 per step),
/// AVX2 (8) or scalar, with the same calls in the same order.
template <class Visit>
inline bool for_each_overlapping(const std::uint32_t* boxes, std::uint32_t begin, std::uint32_t end, std::uint32_t key,
                                 Visit&& visit) {
  std::uint32_t r = begin;
#if defined(__AVX512BW__)
  const __m512i k = _mm512_set1_epi32(static_cast<int>(key));
  for (; r < end; r += 16) {
    const std::uint32_t left = end - r;
    const __mmask16 valid = left >= 16 ? __mmask16(0xffff) : __mmask16((1u << left) - 1u);
    const __m512i b = _mm512_maskz_loadu_epi32(valid, boxes + r);
    for (std::uint32_t pass = _mm512_mask_cmpeq_epi32_mask(valid, _mm512_max_epu8(b, k), k); pass != 0; pass &= pass - 1)
      if (visit(r + static_cast<std::uint32_t>(std::countr_zero(pass)))) return true;
  }
  return false;  // the masked loads covered the tail
#else
#if defined(__AVX2__)
  const __m256i k = _mm256_set1_epi32(static_cast<int>(key));
  for (; r + 8 <= end; r += 8) {
    const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(boxes + r));
    const __m256i same = _mm256_cmpeq_epi32(_mm256_max_epu8(b, k), k);
    for (auto pass = static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_castsi256_ps(same))); pass != 0; pass &= pass - 1)
      if (visit(r + static_cast<std::uint32_t>(std::countr_zero(pass)))) return true;
  }
#endif
  for (; r < end; ++r)
    if (footprint_overlaps(boxes[r], key) && visit(r)) return true;
  return false;
#endif
}

}  // namespace vf::beam
