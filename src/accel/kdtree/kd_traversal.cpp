// Front-to-back stack traversal of the kd layout (the TA_rec_B / pbrt scheme with a fixed stack).
//
// Robustness. A computed plane distance ts = (split - org) * (1/dir) is within a few ulps of the
// exact one (relative), so every interval bound derived from a plane is widened by a relative
// 2^-20, and a child is skipped only when the raw ts lies outside the widened interval: a cell the
// ray truly enters is never skipped because of rounding. Where 1/dir overflows (a zero component,
// or a denormal one) the reciprocal is NaN, so that ts is NaN and both children are visited with
// the full interval: a parallel ray a denormal distance off a plane can hit triangles beyond it,
// whose edge products underflow to zero in the watertight test. Likewise the watertight test may
// report a hit up to a lateral error (2^-18 of the farthest coordinate) across its triangle's edge,
// so a plane crossing is widened by that error over the direction's component across the plane: a
// ray nearly parallel to a plane (a component of 1e-37 beside 1e16) visits both of its sides.
//
// Block boxes. A leaf tests a block only when the ray meets the block's box (its triangles'
// bounds clipped to the leaf cell) within [tmin, best t] grown by the hit slack below, with the
// plane distances widened as above. The exact hit point of a triangle lies in the closed cell of a
// leaf referencing it, hence in that leaf's box of the block holding the triangle, so the box test
// never drops the hit that the loop below would keep.
//
// Exactness. Leaves run the oracle's block kernel (bit-identical to intersect_triangle). A leaf
// tests its triangles against the whole [tmin, best t] of the ray, not only against its own cell
// interval, and the best hit is kept across leaves. The t a triangle test computes may be off from
// the exact hit by a few ulps of the farthest scene coordinate seen from the origin (in ray units),
// which can be large relative to a small t; so the cells walked are those meeting [tmin, tmax]
// grown by a slack covering that error (relative 2^-16 plus 2^-18 of the farthest coordinate), and
// a pending cell is skipped only when it starts beyond the best t plus the same slack. Since every
// point of a triangle lies in the closed box of some leaf referencing it, the hit the brute-force
// loop reports is always tested, ties included: results are bit-identical to that loop.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "kdtree/kd_nodes.hpp"

namespace vf::kd {
namespace {

constexpr float kPlaneSlack = 0x1p-20f;
constexpr float kCullRelative = 0x1p-16f;
constexpr float kCullAbsolute = 0x1p-18f;

using Lanes = simd::Lanes<kLeafWidth>;

/// t moved towards -inf by the plane slack (infinities unchanged, as the root box test needs).
inline float widen_down(float t) { return t * (t < 0.0f ? 1.0f + kPlaneSlack : 1.0f - kPlaneSlack); }
/// t moved towards +inf by the plane slack (infinities unchanged).
inline float widen_up(float t) { return t * (t < 0.0f ? 1.0f - kPlaneSlack : 1.0f + kPlaneSlack); }

struct StackEntry {
  std::uint32_t node;
  float t0, t1;
};

/// Per-ray constants of the plane tests. With AVX the origin and reciprocal direction also sit in
/// vector registers, so that a node's axis selects them without a memory round trip (this is on
/// the node-to-node dependency chain).
struct PlaneRay {
  Vec3f org;
  float inv[3];
  bool negative[3];
  unsigned negative_mask = 0;  ///< bit a: dir[a] has its sign bit set
#if defined(__AVX__)
  __m128 org4, inv4;
#endif

  explicit PlaneRay(const Ray& ray) : org(ray.org) {
    for (int a = 0; a < 3; ++a) {
      // NaN where 1 / dir overflows (a zero component, or a denormal one): the planes of that axis
      // are then met anywhere, and both sides are visited. A ray parallel to a plane at a tiny
      // distance from it can hit the triangles beyond it (the watertight test's products underflow
      // to an edge), and one whose reciprocal overflowed meets planes at finite t, not at infinity.
      inv[a] = 1.0f / ray.dir[a];
      if (std::isinf(inv[a])) inv[a] = std::copysign(std::numeric_limits<float>::quiet_NaN(), ray.dir[a]);
      negative[a] = std::signbit(ray.dir[a]);
      negative_mask |= (negative[a] ? 1u : 0u) << a;
    }
#if defined(__AVX__)
    org4 = _mm_setr_ps(org.x, org.y, org.z, 0.0f);
    inv4 = _mm_setr_ps(inv[0], inv[1], inv[2], 0.0f);
#endif
  }

  /// (split - org[axis]) * (1 / dir[axis]).
  float plane_distance(int axis, float split) const {
#if defined(__AVX__)
    const __m128i lane = _mm_cvtsi32_si128(axis);
    return (split - _mm_cvtss_f32(_mm_permutevar_ps(org4, lane))) * _mm_cvtss_f32(_mm_permutevar_ps(inv4, lane));
#else
    return (split - org[axis]) * inv[axis];
#endif
  }
};

/// Bounds on how far a triangle test's t may lie from the exact hit distance, for one ray.
struct HitSlack {
  float absolute;
  float lateral;  ///< How far across the ray a reported hit may lie from its triangle (world units).

  HitSlack(const Ray& ray, const Bounds3f& scene) {
    const Vec3f reach = abs(ray.org - scene.center()) + scene.extent() * 0.5f;
    lateral = kCullAbsolute * max_component(reach);
    absolute = lateral / max_component(abs(ray.dir));
  }
  float below(float t) const { return t - std::fabs(t) * kCullRelative - absolute; }
  float above(float t) const { return t + std::fabs(t) * kCullRelative + absolute; }
};

/// The ray against the boxes of kBoxWidth consecutive leaf blocks at once (KdLayout::box_lo/hi).
class BlockBoxRay {
 public:
  using BoxLanes = simd::Lanes<kBoxWidth>;

  /// `pad`: each axis's plane pad (traverse()'s), subtracted from near and added to far distances.
  BlockBoxRay(const KdLayout& kd, const PlaneRay& r, const float* pad) {
    for (int a = 0; a < 3; ++a) {
      // Along a negative direction the upper face is entered first.
      near_[a] = (r.negative[a] ? kd.box_hi[a] : kd.box_lo[a]).data();
      far_[a] = (r.negative[a] ? kd.box_lo[a] : kd.box_hi[a]).data();
      org_[a] = BoxLanes::broadcast(r.org[a]);
      inv_[a] = BoxLanes::broadcast(r.inv[a]);
      pad_[a] = BoxLanes::broadcast(pad[a]);
    }
  }

  /// Blocks first .. first + kBoxWidth - 1 whose box the ray may meet within [t0, t1]. Plane
  /// distances are widened as in the traversal; a NaN one (origin in a face plane of a parallel
  /// ray) leaves the interval unchanged, so a block is never skipped for rounding.
  simd::LaneBits test(std::uint32_t first, float t0, float t1) const {
    const BoxLanes down = BoxLanes::broadcast(1.0f - kPlaneSlack), up = BoxLanes::broadcast(1.0f + kPlaneSlack);
    BoxLanes lo = BoxLanes::broadcast(t0), hi = BoxLanes::broadcast(t1);
    for (int a = 0; a < 3; ++a) {
      const BoxLanes near = (load(near_[a] + first) - org_[a]) * inv_[a];
      const BoxLanes far = (load(far_[a] + first) - org_[a]) * inv_[a];
      // The smaller (larger) of the two scalings moves towards -inf (+inf) whatever the sign.
      lo = max_nan_second(min_nan_second(near * down, near * up) - pad_[a], lo);
      hi = min_nan_second(max_nan_second(far * down, far * up) + pad_[a], hi);
    }
    return cmp_le(lo, hi);
  }

 private:
  static BoxLanes load(const float* p) {
    alignas(64) float lanes[kBoxWidth];
    std::memcpy(lanes, p, sizeof(lanes));
    return BoxLanes::load(lanes);
  }
  const float* near_[3];
  const float* far_[3];
  BoxLanes org_[3], inv_[3], pad_[3];
};

/// Clips [t0, t1] to the root box; false when the ray misses it. A NaN slab distance (origin
/// exactly on a slab plane of a zero direction component) leaves the interval unchanged.
bool clip_to_root(const Bounds3f& box, const PlaneRay& r, const float* pad, float& t0, float& t1) {
  for (int a = 0; a < 3; ++a) {
    const float near = widen_down(((r.negative[a] ? box.hi[a] : box.lo[a]) - r.org[a]) * r.inv[a]) - pad[a];
    const float far = widen_up(((r.negative[a] ? box.lo[a] : box.hi[a]) - r.org[a]) * r.inv[a]) + pad[a];
    t0 = near > t0 ? near : t0;
    t1 = far < t1 ? far : t1;
  }
  return t0 <= t1 && t0 < std::numeric_limits<float>::infinity();
}

struct BestHit {
  float t = 0, u = 0, v = 0;
  std::uint32_t triangle = kInvalidId;
  std::size_t slot = 0;  ///< Block lane of the hit (block * kLeafWidth + lane).
};

template <bool kAnyHit>
bool traverse(const KdLayout& kd, const Ray& ray, BestHit& best) {
  if (kd.nodes.empty()) return false;
  const PlaneRay r(ray);
  const HitSlack slack(ray, kd.bounds);
  const float slack_tmin = slack.below(ray.tmin);
  float t0 = slack_tmin, t1 = slack.above(ray.tmax);
  // A plane crossing's t may be off by the lateral error over the direction's component across the
  // plane: huge for a ray nearly parallel to it, whose reported hit can lie across it.
  const float plane_pad[3] = {slack.lateral / std::fabs(ray.dir.x), slack.lateral / std::fabs(ray.dir.y), slack.lateral / std::fabs(ray.dir.z)};
  const BlockBoxRay boxes(kd, r, plane_pad);
  if (!clip_to_root(kd.bounds, r, plane_pad, t0, t1)) return false;
  const simd::BlockRay<kLeafWidth> tri_ray{WatertightRay(ray)};
  const Lanes tri_tmin = Lanes::broadcast(ray.tmin);
  Lanes tri_tmax = Lanes::broadcast(ray.tmax);
  best.t = ray.tmax;
  float cull = t1;

  const KdNode* nodes = kd.nodes.data();
  const LeafBlock* blocks = kd.blocks.data();
  const std::uint32_t* lane_triangle = kd.lane_triangle.data();
  StackEntry stack[kMaxDepth];
  int sp = 0;
  std::uint32_t index = 0;
  for (;;) {
    const KdNode node = nodes[index];
    if (!node.is_leaf()) {
      const int axis = node.axis();
      const float ts = r.plane_distance(axis, node.split());
      const std::uint32_t below = index + 1, above = node.right_child();
      // Along the ray, the half-space below the plane comes first unless dir[axis] is negative.
      const bool negative = (r.negative_mask >> axis) & 1u;
      const std::uint32_t first = negative ? above : below;
      const std::uint32_t second = negative ? below : above;
      // The plane tests compare the raw ts with bounds that are already widened, which keeps the
      // widening off the node-to-node dependency chain. Written so that a NaN ts (origin in the
      // plane of a parallel ray) visits both children with the full interval, and so that the
      // choice compiles to conditional moves.
      const float pad = plane_pad[axis];
      const bool visit_first = !(ts + pad < t0), visit_second = !(ts - pad > t1);
      const float ts_lo = ts - std::fabs(ts) * kPlaneSlack - pad, ts_hi = ts + std::fabs(ts) * kPlaneSlack + pad;
      const float second_t0 = ts_lo > t0 ? ts_lo : t0;
      stack[sp] = {second, second_t0, t1};
      sp += visit_first && visit_second ? 1 : 0;
      index = visit_first ? first : second;
      t0 = visit_first ? t0 : second_t0;
      t1 = visit_first && ts_hi < t1 ? ts_hi : t1;
      continue;
    }

    // The blocks come in groups of kBoxWidth; only those whose box the ray meets are tested.
    const std::uint32_t first_block = node.leaf_first();
    const std::uint32_t end_block = first_block + block_count(node.leaf_count());
    for (std::uint32_t group = first_block; group < end_block; group += kBoxWidth) {
      const std::uint32_t in_group = std::min<std::uint32_t>(end_block - group, kBoxWidth);
      simd::LaneBits candidates = boxes.test(group, slack_tmin, cull) & ((1u << in_group) - 1u);
      for (; candidates != 0; candidates &= candidates - 1) {
        const std::uint32_t b = group + static_cast<std::uint32_t>(simd::first_lane(candidates));
        if constexpr (kAnyHit) {
          if (simd::intersect_block<kLeafWidth, false>(blocks[b], tri_ray, tri_tmin, tri_tmax, nullptr) != 0) return true;
        } else {
          simd::BlockHits<kLeafWidth> hits;
          simd::LaneBits lanes = simd::intersect_block<kLeafWidth, true>(blocks[b], tri_ray, tri_tmin, tri_tmax, &hits);
          if (lanes == 0) continue;
          for (; lanes != 0; lanes &= lanes - 1) {
            const int l = simd::first_lane(lanes);
            const std::size_t slot = std::size_t{b} * kLeafWidth + static_cast<std::uint32_t>(l);
            const std::uint32_t triangle = lane_triangle[slot];
            // Lanes are not in index order, and a block may hit several times: equal t, lowest index.
            if (hits.t[l] < best.t || (hits.t[l] == best.t && triangle < best.triangle))
              best = {hits.t[l], hits.u[l], hits.v[l], triangle, slot};
          }
          tri_tmax = Lanes::broadcast(best.t);
          cull = slack.above(best.t);
        }
      }
    }
    do {
      if (sp == 0) return best.triangle != kInvalidId;
      --sp;
    } while (stack[sp].t0 > cull);
    index = stack[sp].node;
    t0 = stack[sp].t0;
    t1 = stack[sp].t1;
  }
}

}  // namespace

Hit intersect(const KdLayout& kd, const Ray& ray) {
  BestHit best;
  if (!traverse<false>(kd, ray, best)) return Hit{};
  return Hit::triangle(best.t, best.u, best.v, kd.prim[best.triangle], kd.instance[best.triangle],
                       kd.blocks[best.slot / kLeafWidth].normal(static_cast<int>(best.slot % kLeafWidth)));
}

bool occluded(const KdLayout& kd, const Ray& ray) {
  BestHit unused;
  return traverse<true>(kd, ray, unused);
}

std::size_t KdLayout::memory_bytes() const {
  std::size_t box_floats = 0;
  for (int axis = 0; axis < 3; ++axis) box_floats += box_lo[axis].capacity() + box_hi[axis].capacity();
  return nodes.capacity() * sizeof(KdNode) + blocks.capacity() * sizeof(LeafBlock) + box_floats * sizeof(float) +
         (lane_triangle.capacity() + prim.capacity() + instance.capacity()) * sizeof(std::uint32_t);
}

}  // namespace vf::kd
