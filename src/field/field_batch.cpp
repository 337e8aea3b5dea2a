// ObjectField::trace_batch: trace() for 16 rays at a time with AVX-512. Each step is trace()'s
// formula on 16 lanes, in the same order and without fused multiply-adds, except the arctangents
// (a polynomial, |error| < 2e-6 rad, where trace() calls atan2) and the reads (gathers).

#include <cmath>
#include <limits>

#include "visfield/field/object_field.hpp"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace vf::field {

#if defined(__AVX512F__)
namespace {

using F = __m512;
using I = __m512i;
using M = __mmask16;

constexpr float kPi = 3.14159265358979323846f;

inline F splat(float x) { return _mm512_set1_ps(x); }
inline I splat_i(int x) { return _mm512_set1_epi32(x); }
inline F abs(F a) { return _mm512_abs_ps(a); }
inline F sqrt(F a) { return _mm512_sqrt_ps(a); }
inline F max(F a, F b) { return _mm512_max_ps(a, b); }
inline F select(M m, F if_true, F if_false) { return _mm512_mask_blend_ps(m, if_false, if_true); }
inline I select(M m, I if_true, I if_false) { return _mm512_mask_blend_epi32(m, if_false, if_true); }
inline M less(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
inline M less_equal(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
inline M greater(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
inline M greater_equal(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ); }
inline F dot(F ax, F ay, F az, F bx, F by, F bz) { return ax * bx + ay * by + az * bz; }
inline F copysign(F magnitude, F sign) {
  const I sign_bit = splat_i(static_cast<int>(0x80000000u));
  return _mm512_castsi512_ps(_mm512_or_si512(_mm512_andnot_si512(sign_bit, _mm512_castps_si512(magnitude)),
                                             _mm512_and_si512(sign_bit, _mm512_castps_si512(sign))));
}

/// atan(x) for x in [-1, 1], |error| < 2e-6 rad (odd minimax polynomial of degree 11).
inline F atan_unit(F x) {
  const F x2 = x * x;
  F p = splat(-0.01172120f);
  p = _mm512_fmadd_ps(p, x2, splat(0.05265332f));
  p = _mm512_fmadd_ps(p, x2, splat(-0.11643287f));
  p = _mm512_fmadd_ps(p, x2, splat(0.19354346f));
  p = _mm512_fmadd_ps(p, x2, splat(-0.33262347f));
  p = _mm512_fmadd_ps(p, x2, splat(0.99997726f));
  return x * p;
}

/// atan2(y, x) for y, x >= 0 (0 when both are 0).
inline F atan2_first_quadrant(F y, F x) {
  const M steep = greater(y, x);
  const F big = max(x, y), small = _mm512_min_ps(x, y);
  const F ratio = select(greater(big, splat(0.0f)), small / big, splat(0.0f));
  const F a = atan_unit(ratio);
  return select(steep, splat(kPi / 2) - a, a);
}

/// Inverse concentric map of disk point (x, y) to (s, t), as disk_to_concentric().
inline void disk_to_square(F x, F y, F& s, F& t) {
  const F r = sqrt(x * x + y * y);
  const M x_major = greater_equal(abs(x), abs(y));
  const M zero = _mm512_cmp_ps_mask(r, splat(0.0f), _CMP_EQ_OQ);
  const F numerator = select(x_major, y, x), denominator = select(x_major, x, y);
  const F ratio = numerator / select(zero, splat(1.0f), denominator);
  const F major = copysign(r, denominator);
  const F minor = major * splat(4.0f / kPi) * atan_unit(ratio);
  const F a = select(zero, splat(0.0f), select(x_major, major, minor));
  const F b = select(zero, splat(0.0f), select(x_major, minor, major));
  s = (a + splat(1.0f)) / splat(2.0f);
  t = (b + splat(1.0f)) / splat(2.0f);
}

/// Dense index of lattice point (i, j) of half-width n (octa::point_index on lanes).
inline I point_index(I i, I j, int n) {
  const I n_v = splat_i(n);
  const I left = _mm512_mullo_epi32(_mm512_add_epi32(i, n_v), _mm512_add_epi32(i, n_v));
  const I right = _mm512_sub_epi32(_mm512_add_epi32(splat_i(n * n), _mm512_mullo_epi32(splat_i(2 * n + 2), i)), _mm512_mullo_epi32(i, i));
  const M non_positive = _mm512_cmple_epi32_mask(i, _mm512_setzero_si512());
  const I row_start = _mm512_mask_blend_epi32(non_positive, right, left);
  return _mm512_sub_epi32(_mm512_add_epi32(_mm512_add_epi32(row_start, j), n_v), _mm512_abs_epi32(i));
}

inline F gather(const float* base, I index, M active) {
  return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), active, index, base, 4);
}

}  // namespace
#endif

void ObjectField::trace_batch(const ObjectRays& rays, FieldAnswer* out) const {
  std::size_t done = 0;
#if defined(__AVX512F__)
  const bool paper_lookups =
      config_.direction_lookup == DirectionLookup::nearest && config_.position_lookup == PositionLookup::nearest;
  if (paper_lookups && cells_.size() < (std::size_t{1} << 31)) {
    const int n = positions_.lattice_size(), cells_per_side = config_.directions;
    const std::size_t count = positions_.size(), upper = count / 2;
    const float* rows = lookup_rows_.data();
    const float* frame_rows = rows + 3 * upper;
    const F cx = splat(sphere_.centre.x), cy = splat(sphere_.centre.y), cz = splat(sphere_.centre.z);
    const float r = sphere_.radius, diameter = 2.0f * r;
    const I stride = splat_i(static_cast<int>(sample_stride_));
    const int* table = reinterpret_cast<const int*>(cells_.data());
    for (; done + 16 <= rays.count; done += 16) {
      const std::size_t at = done;
      const F ox = _mm512_loadu_ps(rays.ox + at), oy = _mm512_loadu_ps(rays.oy + at), oz = _mm512_loadu_ps(rays.oz + at);
      F dx = _mm512_loadu_ps(rays.dx + at), dy = _mm512_loadu_ps(rays.dy + at), dz = _mm512_loadu_ps(rays.dz + at);
      // Unit direction and the ray's range in its units.
      const F len = sqrt(dot(dx, dy, dz, dx, dy, dz));
      const F inv = splat(1.0f) / len;
      dx = dx * inv;
      dy = dy * inv;
      dz = dz * inv;
      const F s_min = _mm512_loadu_ps(rays.tmin + at) * len, s_max = _mm512_loadu_ps(rays.tmax + at) * len;
      // The bounding sphere.
      const F ocx = ox - cx, ocy = oy - cy, ocz = oz - cz;
      const F b = dot(ocx, ocy, ocz, dx, dy, dz), c = dot(ocx, ocy, ocz, ocx, ocy, ocz) - splat(r * r);
      const F disc = b * b - c;
      M active = greater_equal(disc, splat(0.0f));
      const F root = sqrt(max(disc, splat(0.0f)));
      const F s_enter = splat(0.0f) - b - root, s_exit = splat(0.0f) - b + root;
      const M inside = less_equal(c, splat(0.0f));
      active &= inside | greater_equal(s_enter, splat(0.0f));
      if (!active) {
        for (int lane = 0; lane < 16; ++lane) out[at + lane] = {};
        continue;
      }
      // The point where the ray meets the sphere (entry from outside, exit from inside), as a unit
      // direction from the centre, and the direction the table is read in.
      const F s_at = select(inside, s_exit, s_enter);
      F ex = ocx + dx * s_at, ey = ocy + dy * s_at, ez = ocz + dz * s_at;
      const F e_inv = splat(1.0f) / sqrt(dot(ex, ey, ez, ex, ey, ez));
      ex = ex * e_inv;
      ey = ey * e_inv;
      ez = ez * e_inv;
      const F qx = select(inside, splat(0.0f) - dx, dx), qy = select(inside, splat(0.0f) - dy, dy),
              qz = select(inside, splat(0.0f) - dz, dz);

      // Nearest positional sample: fold to the upper hemisphere, invert the lattice map, take the
      // corner of the containing lattice triangle with the largest cosine.
      const M lower = less(ez, splat(0.0f));
      const F fz = abs(ez);
      const F radial = sqrt(max(splat(0.0f), splat(1.0f) - fz));
      const F phi = atan2_first_quadrant(abs(ey), abs(ex));
      const F v = radial * phi / splat(kPi / 2), u = radial - v;
      const F n_f = splat(static_cast<float>(n));
      const F la = select(greater(ex, splat(0.0f)), n_f * u, select(less(ex, splat(0.0f)), splat(0.0f) - n_f * u, splat(0.0f)));
      const F lb = select(greater(ey, splat(0.0f)), n_f * v, select(less(ey, splat(0.0f)), splat(0.0f) - n_f * v, splat(0.0f)));
      const I i0 = _mm512_min_epi32(_mm512_max_epi32(_mm512_cvttps_epi32(_mm512_floor_ps(la)), splat_i(-n)), splat_i(n - 1));
      const I j0 = _mm512_min_epi32(_mm512_max_epi32(_mm512_cvttps_epi32(_mm512_floor_ps(lb)), splat_i(-n)), splat_i(n - 1));
      const F f = la - _mm512_cvtepi32_ps(i0), g = lb - _mm512_cvtepi32_ps(j0);
      const M same = static_cast<M>(~(_mm512_cmplt_epi32_mask(i0, _mm512_setzero_si512()) ^
                                      _mm512_cmplt_epi32_mask(j0, _mm512_setzero_si512())));
      const M case_b = same & greater(f + g, splat(1.0f));
      const M case_c = static_cast<M>(~same) & less_equal(g, f);
      const M case_d = static_cast<M>(~same) & greater(g, f);
      const I one = splat_i(1);
      const I i1 = _mm512_add_epi32(i0, one), j1 = _mm512_add_epi32(j0, one);
      const I corner_i[3] = {select(case_b, i1, i0), select(case_d, i0, i1), select(case_c | case_d, i1, i0)};
      const I corner_j[3] = {select(case_b, j1, j0), select(case_d, j1, j0), j1};
      F best_cos = splat(-2.0f);
      I best = _mm512_setzero_si512();
      for (int k = 0; k < 3; ++k) {
        const M inside_rim =
            _mm512_cmple_epi32_mask(_mm512_add_epi32(_mm512_abs_epi32(corner_i[k]), _mm512_abs_epi32(corner_j[k])), splat_i(n));
        const M live = active & inside_rim;
        const I index = select(live, point_index(corner_i[k], corner_j[k], n), _mm512_setzero_si512());
        const F wx = gather(rows, index, live), wy = gather(rows + upper, index, live), wz = gather(rows + 2 * upper, index, live);
        const F cosine = dot(ex, ey, fz, wx, wy, wz);
        const M better = live & greater(cosine, best_cos);
        best_cos = select(better, cosine, best_cos);
        best = select(better, index, best);
      }
      const I sample = _mm512_mask_add_epi32(best, lower, best, splat_i(static_cast<int>(upper)));

      // The direction in the sample's hemisphere frame, then its cell.
      F frame[9];
      for (int row = 0; row < 9; ++row) frame[row] = gather(frame_rows + static_cast<std::size_t>(row) * count, sample, active);
      F lx = dot(frame[0], frame[1], frame[2], qx, qy, qz);
      F ly = dot(frame[3], frame[4], frame[5], qx, qy, qz);
      F lz = dot(frame[6], frame[7], frame[8], qx, qy, qz);
      const M grazing = less(lz, splat(0.0f));
      if (grazing) {
        const F planar = sqrt(lx * lx + ly * ly);
        const M flat = _mm512_cmp_ps_mask(planar, splat(0.0f), _CMP_GT_OQ);
        lx = select(grazing, select(flat, lx / planar, splat(0.0f)), lx);
        ly = select(grazing, select(flat, ly / planar, splat(0.0f)), ly);
        lz = select(grazing, select(flat, splat(0.0f), splat(1.0f)), lz);
      }
      F s, t;
      switch (config_.mapping) {
        case HemisphereMapping::polar: {
          F azimuth = atan2_first_quadrant(abs(ly), abs(lx));
          azimuth = select(less(lx, splat(0.0f)), splat(kPi) - azimuth, azimuth);
          azimuth = select(less(ly, splat(0.0f)), splat(2.0f * kPi) - azimuth, azimuth);
          s = azimuth / splat(2.0f * kPi);
          s = select(greater_equal(s, splat(1.0f)), splat(0.0f), s);
          t = atan2_first_quadrant(sqrt(lx * lx + ly * ly), lz) / splat(kPi / 2);
          break;
        }
        case HemisphereMapping::rejection_malley:
          s = (lx + splat(1.0f)) / splat(2.0f);
          t = (ly + splat(1.0f)) / splat(2.0f);
          break;
        case HemisphereMapping::concentric_malley:
          disk_to_square(lx, ly, s, t);
          break;
        case HemisphereMapping::concentric_equal_area:
        default: {
          const F k = splat(1.0f) / sqrt(splat(1.0f) + max(splat(0.0f), lz));
          disk_to_square(lx * k, ly * k, s, t);
          break;
        }
      }
      const F side = splat(static_cast<float>(cells_per_side));
      const I ci = _mm512_min_epi32(_mm512_max_epi32(_mm512_cvttps_epi32(s * side), _mm512_setzero_si512()), splat_i(cells_per_side - 1));
      const I cj = _mm512_min_epi32(_mm512_max_epi32(_mm512_cvttps_epi32(t * side), _mm512_setzero_si512()), splat_i(cells_per_side - 1));
      const I cell = _mm512_add_epi32(_mm512_mullo_epi32(cj, splat_i(cells_per_side)), ci);
      const I sample_base = _mm512_mullo_epi32(sample, stride);

      // The cell's code, decoded.
      M cell_hit;
      F x;
      switch (config_.storage) {
        case CellStorage::u8: {
          const I code = _mm512_and_si512(
              _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), active, _mm512_add_epi32(sample_base, cell), table, 1), splat_i(0xFF));
          cell_hit = _mm512_cmple_epi32_mask(code, splat_i(254));
          x = _mm512_cvtepi32_ps(code) / splat(254.0f);
          break;
        }
        case CellStorage::u16: {
          const I offset = _mm512_add_epi32(sample_base, _mm512_add_epi32(cell, cell));
          const I code = _mm512_and_si512(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), active, offset, table, 1), splat_i(0xFFFF));
          cell_hit = _mm512_cmple_epi32_mask(code, splat_i(65534));
          x = _mm512_cvtepi32_ps(code) / splat(65534.0f);
          break;
        }
        case CellStorage::f32: {
          const I offset = _mm512_add_epi32(sample_base, _mm512_slli_epi32(cell, 2));
          x = _mm512_mask_i32gather_ps(_mm512_setzero_ps(), active, offset, table, 1);
          cell_hit = less_equal(x, splat(1.5f));
          break;
        }
        case CellStorage::bit:
        default: {
          const I offset = _mm512_add_epi32(sample_base, _mm512_srli_epi32(cell, 3));
          const I word = _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), active, offset, table, 1);
          const I bit = _mm512_sllv_epi32(one, _mm512_and_si512(cell, splat_i(7)));
          cell_hit = _mm512_test_epi32_mask(word, bit);
          x = gather(averages_.data(), sample, active & cell_hit);
          break;
        }
      }
      // Inter-object: entry plus the stored distance; intra-object: exit minus it, beyond the
      // start surface's offset.
      const F d = splat(diameter);
      const F s_hit = select(inside, s_exit - x * d, s_enter + x * d);
      M hit = active & cell_hit & greater_equal(s_hit, s_min) & less_equal(s_hit, s_max);
      hit &= static_cast<M>(~inside) | greater(s_hit, splat(self_offset_ * diameter));
      alignas(64) float t_out[16];
      _mm512_store_ps(t_out, s_hit / len);
      for (int lane = 0; lane < 16; ++lane)
        out[at + static_cast<std::size_t>(lane)] = (hit >> lane) & 1u ? FieldAnswer{true, t_out[lane]} : FieldAnswer{};
    }
  }
#endif
  for (; done < rays.count; ++done)
    out[done] = trace({rays.ox[done], rays.oy[done], rays.oz[done]}, {rays.dx[done], rays.dy[done], rays.dz[done]},
                      rays.tmin[done], rays.tmax[done]);
}

}  // namespace vf::field
