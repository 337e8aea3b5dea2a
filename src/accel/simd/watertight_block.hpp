#pragma once
/// \file The watertight ray–triangle test of core/triangle_intersect.hpp evaluated on W triangles
/// against one ray (BruteForce, the Bvh leaves, BeamField's leaves) or on W parallel rays against one
/// triangle (BeamField's per-tile packets). Each lane performs exactly the operations of
/// intersect_triangle(), in the same order and precision (the double-precision edge fallback runs
/// per lane in scalar code), so every lane's hit/miss, t, u and v are bit-identical to it.

#include <cstdint>
#include <limits>

#include "simd/lanes.hpp"
#include "visfield/core/triangle_intersect.hpp"

namespace vf::simd {

/// W triangles, structure of arrays: p[((corner * 3) + axis) * W + lane]. Unused lanes hold NaN
/// corners, which never hit.
template <int W>
struct alignas(W * 4 > 64 ? 64 : W * 4) TriangleBlock {
  float p[9 * W];

  /// The W values of coordinate `axis` of corner `corner`.
  const float* row(int corner, int axis) const { return p + (corner * 3 + axis) * W; }
  /// Puts triangle (c0, c1, c2) into `lane`.
  void set(int lane, const Vec3f& c0, const Vec3f& c1, const Vec3f& c2) {
    const Vec3f* corners[3] = {&c0, &c1, &c2};
    for (int k = 0; k < 3; ++k)
      for (int axis = 0; axis < 3; ++axis) p[(k * 3 + axis) * W + lane] = (*corners[k])[axis];
  }
  /// Corner `corner` (0..2) of the triangle in `lane`.
  Vec3f corner(int lane, int corner) const {
    return {row(corner, 0)[lane], row(corner, 1)[lane], row(corner, 2)[lane]};
  }
  /// Geometric normal of the triangle in `lane`: cross(p1 - p0, p2 - p0), not normalised (a Hit's normal).
  Vec3f normal(int lane) const {
    const Vec3f p0 = corner(lane, 0);
    return cross(corner(lane, 1) - p0, corner(lane, 2) - p0);
  }
  /// Makes `lane` empty (NaN corners).
  void clear(int lane) {
    for (int k = 0; k < 9; ++k) p[k * W + lane] = std::numeric_limits<float>::quiet_NaN();
  }
};

/// Per-ray constants of the block test (the WatertightRay's), broadcast to W lanes where a block is
/// tested. Build once per ray.
template <int W>
struct BlockRay {
  int kx, ky, kz;
  float org_x, org_y, org_z;  ///< org[kx], org[ky], org[kz]
  float sx, sy, sz;

  explicit BlockRay(const WatertightRay& r) : BlockRay(r.kx, r.ky, r.kz, r.org[r.kx], r.org[r.ky], r.org[r.kz], r.sx, r.sy, r.sz) {}
  /// From the WatertightRay fields computed elsewhere (bit-identically), the origin already permuted.
  BlockRay(int kx_, int ky_, int kz_, float org_x_, float org_y_, float org_z_, float sx_, float sy_, float sz_)
      : kx(kx_), ky(ky_), kz(kz_), org_x(org_x_), org_y(org_y_), org_z(org_z_), sx(sx_), sy(sy_), sz(sz_) {}
};

/// t, u, v of every lane of one block test (meaningful in hit lanes only).
template <int W>
struct BlockHits {
  alignas(W * 4 > 64 ? 64 : W * 4) float t[W];
  alignas(W * 4 > 64 ? 64 : W * 4) float u[W];
  alignas(W * 4 > 64 ? 64 : W * 4) float v[W];
};

namespace detail {

// intersect_triangle's fallback for lanes with a zero edge value: all three edge values again in
// double from the same float inputs. Rare (rays through edges or vertices, grazing rays).
template <int W>
inline void recompute_edges_in_double(LaneBits lanes, const Lanes<W> (&xy)[6], Lanes<W>& e0, Lanes<W>& e1,
                                      Lanes<W>& e2) {
  alignas(64) float v[6][W];
  alignas(64) float e[3][W];
  for (int i = 0; i < 6; ++i) xy[i].store(v[i]);
  e0.store(e[0]);
  e1.store(e[1]);
  e2.store(e[2]);
  for (; lanes != 0; lanes &= lanes - 1) {
    const int l = first_lane(lanes);
    const float ax = v[0][l], ay = v[1][l], bx = v[2][l], by = v[3][l], cx = v[4][l], cy = v[5][l];
    e[0][l] = static_cast<float>(static_cast<double>(cx) * by - static_cast<double>(cy) * bx);
    e[1][l] = static_cast<float>(static_cast<double>(ax) * cy - static_cast<double>(ay) * cx);
    e[2][l] = static_cast<float>(static_cast<double>(bx) * ay - static_cast<double>(by) * ax);
  }
  e0 = Lanes<W>::load(e[0]);
  e1 = Lanes<W>::load(e[1]);
  e2 = Lanes<W>::load(e[2]);
}

}  // namespace detail

/// The watertight test's decision from the corners relative to the ray origins (a = p0 - org, ...,
/// each permuted to kx, ky, kz) and the shear: intersect_triangle()'s operations after its
/// subtraction, lane by lane. Lanes whose a_x is NaN are unused. With kWantHits the t, u, v of the hit
/// lanes are written to `hits`.
template <int W, bool kWantHits>
inline LaneBits hit_lanes(const Lanes<W>& a_x, const Lanes<W>& a_y, const Lanes<W>& a_z, const Lanes<W>& b_x, const Lanes<W>& b_y,
                          const Lanes<W>& b_z, const Lanes<W>& c_x, const Lanes<W>& c_y, const Lanes<W>& c_z, const Lanes<W>& sx,
                          const Lanes<W>& sy, const Lanes<W>& sz, const Lanes<W>& tmin, const Lanes<W>& tmax, BlockHits<W>* hits) {
  using V = Lanes<W>;
  const V ax = a_x - sx * a_z, ay = a_y - sy * a_z;
  const V bx = b_x - sx * b_z, by = b_y - sy * b_z;
  const V cx = c_x - sx * c_z, cy = c_y - sy * c_z;
  V e0 = cx * by - cy * bx;
  V e1 = ax * cy - ay * cx;
  V e2 = bx * ay - by * ax;
  const V zero = V::broadcast(0.0f);
  // intersect_triangle rejects when some edge value is < 0 and some is > 0. Unused lanes (NaN
  // corners or origins) are dropped here as well; real triangles have finite corners, so a NaN edge
  // value of theirs (an overflow) stays a candidate, exactly as in the scalar test.
  const auto mixed_signs = [&] {
    return (cmp_lt(e0, zero) | cmp_lt(e1, zero) | cmp_lt(e2, zero)) &
           (cmp_gt(e0, zero) | cmp_gt(e1, zero) | cmp_gt(e2, zero));
  };
  const LaneBits used = cmp_ord(a_x, a_x);
  LaneBits candidates = used & ~mixed_signs();
  if (candidates == 0) return 0;
  // The double-precision fallback for lanes with a zero edge value. Only candidates need it: a
  // float edge value is either exact in sign or zero (rounding is monotonic, and the products are
  // exact in double), so a lane rejected for strictly mixed signs is rejected after the fallback too.
  const LaneBits on_edge = candidates & (cmp_eq(e0, zero) | cmp_eq(e1, zero) | cmp_eq(e2, zero));
  if (on_edge != 0) {
    const V xy[6] = {ax, ay, bx, by, cx, cy};
    detail::recompute_edges_in_double<W>(on_edge, xy, e0, e1, e2);
    candidates = used & ~mixed_signs();
  }
  const V det = e0 + e1 + e2;
  candidates &= ~cmp_eq(det, zero);
  if (candidates == 0) return 0;
  const V az = sz * a_z, bz = sz * b_z, cz = sz * c_z;
  const V t_scaled = e0 * az + e1 * bz + e2 * cz;
  const V inv_det = V::broadcast(1.0f) / det;
  const V t = t_scaled * inv_det;
  // A t past the largest float is no hit (intersect_triangle()); the minimum keeps a NaN tmax (the
  // second operand survives a NaN), which nothing is at or below.
  const LaneBits hit = candidates & cmp_gt(t, tmin) & cmp_le(t, min_nan_second(V::broadcast(kLargestHitT), tmax));
  if constexpr (kWantHits) {
    if (hit != 0) {
      t.store(hits->t);
      (e1 * inv_det).store(hits->u);
      (e2 * inv_det).store(hits->v);
    }
  }
  return hit;
}

/// Tests the W triangles of `block` against the ray for t in (tmin, tmax] (broadcast); returns the
/// lanes that hit. With kWantHits the t, u, v of those lanes are written to `hits`.
template <int W, bool kWantHits>
inline LaneBits intersect_block(const TriangleBlock<W>& block, const BlockRay<W>& r, const Lanes<W>& tmin,
                                const Lanes<W>& tmax, BlockHits<W>* hits) {
  using V = Lanes<W>;
  // a = p0 - org, b = p1 - org, c = p2 - org (only the permuted components are needed). Corner k
  // of a row lies 3 * W floats after corner k - 1: three base pointers and constant offsets.
  const float* px = block.row(0, r.kx);
  const float* py = block.row(0, r.ky);
  const float* pz = block.row(0, r.kz);
  const V ox = V::broadcast(r.org_x), oy = V::broadcast(r.org_y), oz = V::broadcast(r.org_z);
  const V a_x = V::load(px) - ox, a_y = V::load(py) - oy, a_z = V::load(pz) - oz;
  const V b_x = V::load(px + 3 * W) - ox, b_y = V::load(py + 3 * W) - oy, b_z = V::load(pz + 3 * W) - oz;
  const V c_x = V::load(px + 6 * W) - ox, c_y = V::load(py + 6 * W) - oy, c_z = V::load(pz + 6 * W) - oz;
  return hit_lanes<W, kWantHits>(a_x, a_y, a_z, b_x, b_y, b_z, c_x, c_y, c_z, V::broadcast(r.sx), V::broadcast(r.sy), V::broadcast(r.sz),
                                 tmin, tmax, hits);
}

/// W rays of one direction (their shared WatertightRay constants kx, ky, kz, sx, sy, sz) with their
/// own origins, structure of arrays: org[axis * W + lane] in the permuted axes kx, ky, kz. Unused
/// lanes hold NaN origins, which never hit.
template <int W>
struct alignas(W * 4 > 64 ? 64 : W * 4) RayBlock {
  float org[3 * W];
};

/// Tests triangle (p0, p1, p2) against the W rays of `rays` (sharing `shear`'s direction constants;
/// its origin is ignored) for t in (tmin, tmax] per lane; returns the lanes that hit. Each lane's
/// answer is bit for bit intersect_triangle()'s for that ray.
template <int W>
inline LaneBits intersect_rays(const RayBlock<W>& rays, const BlockRay<W>& shear, const Vec3f& p0, const Vec3f& p1, const Vec3f& p2,
                               const Lanes<W>& tmin, const Lanes<W>& tmax) {
  using V = Lanes<W>;
  const V ox = V::load(rays.org), oy = V::load(rays.org + W), oz = V::load(rays.org + 2 * W);
  const int kx = shear.kx, ky = shear.ky, kz = shear.kz;
  const V a_x = V::broadcast(p0[kx]) - ox, a_y = V::broadcast(p0[ky]) - oy, a_z = V::broadcast(p0[kz]) - oz;
  const V b_x = V::broadcast(p1[kx]) - ox, b_y = V::broadcast(p1[ky]) - oy, b_z = V::broadcast(p1[kz]) - oz;
  const V c_x = V::broadcast(p2[kx]) - ox, c_y = V::broadcast(p2[ky]) - oy, c_z = V::broadcast(p2[kz]) - oz;
  return hit_lanes<W, false>(a_x, a_y, a_z, b_x, b_y, b_z, c_x, c_y, c_z, V::broadcast(shear.sx), V::broadcast(shear.sy),
                             V::broadcast(shear.sz), tmin, tmax, nullptr);
}

}  // namespace vf::simd
