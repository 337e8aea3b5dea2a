// Single-ray traversal of the 8-wide BVH: closest hit and any hit. Boxes are tested conservatively
// (box_test.hpp); leaves run the same block test as BruteForce, and among equal t the lowest
// TriangleSet index wins, so closest hits are identical to the oracle's, ties included.

#include <array>
#include <bit>
#include <cmath>

#include "bvh/box_test.hpp"
#include "bvh/bvh_impl.hpp"

namespace vf {
namespace {

using bvh::kLeafWidth;
using bvh::V8;
using bvh::widen_down;
using bvh::widen_up;
using LeafLanes = simd::Lanes<kLeafWidth>;

constexpr int kStackSize = 7 * bvh::kMaxBinaryDepth + 1;

/// Everything a traversal needs to know about its ray, computed once: the WatertightRay
/// permutation and shear (bit-identical to its constructor) and the box test's reciprocals, with one
/// 8-lane division and no branches (AO directions are random, so branches on them would be
/// mispredicted, and six scalar divisions would cost more than the rest of a short traversal).
struct TraversalRay {
#if defined(__AVX2__)
  // Lanes of (dir.x, dir.y, dir.z, 1) forming the numerator (1, 1, 1, dir[kx], dir[ky], 1, 1, 1) per
  // kz and kx/ky swap, and the denominator (dir.x, dir.y, dir.z, dir[kz] x3, 1, 1) per kz.
  alignas(32) static constexpr int kNumeratorLanes[3][2][8] = {
      {{3, 3, 3, 1, 2, 3, 3, 3}, {3, 3, 3, 2, 1, 3, 3, 3}},
      {{3, 3, 3, 2, 0, 3, 3, 3}, {3, 3, 3, 0, 2, 3, 3, 3}},
      {{3, 3, 3, 0, 1, 3, 3, 3}, {3, 3, 3, 1, 0, 3, 3, 3}}};
  alignas(32) static constexpr int kDenominatorLanes[3][8] = {
      {0, 1, 2, 0, 0, 0, 3, 3}, {0, 1, 2, 1, 1, 1, 3, 3}, {0, 1, 2, 2, 2, 2, 3, 3}};
  static __m256i load_index(const int* lanes) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(lanes)); }
#endif
  bvh::BoxRay box;
  simd::BlockRay<kLeafWidth> triangle;

  explicit TraversalRay(const Ray& ray) : triangle(shear(ray, box)) {}

 private:
  static simd::BlockRay<kLeafWidth> shear(const Ray& ray, bvh::BoxRay& box) {
    const float d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
    const float ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
    // max_axis(|dir|) from the three comparisons it makes: bit 0 x>=y, bit 1 x>=z, bit 2 y>=z.
    static constexpr int kLargest[8] = {2, 2, 2, 0, 1, 2, 1, 0};
    static constexpr int kNext[3] = {1, 2, 0};
    const int kz = kLargest[int(ax >= ay) | (int(ax >= az) << 1) | (int(ay >= az) << 2)];
    int kx = kNext[kz], ky = kNext[kx];
    const int swap = (kx ^ ky) & -int(d[kz] < 0.0f);  // swap kx, ky when dir[kz] < 0 (keeps the winding)
    kx ^= swap;
    ky ^= swap;
#if defined(__AVX2__)
    // The operands are gathered and the quotients spread by register permutes: building them in a
    // stack array with scalar stores and reloading it as a vector stalls on store forwarding,
    // which measured as a sixth of a short AO traversal.
    const int flip = swap != 0 ? 1 : 0;
    const __m256 dir1 = _mm256_castps128_ps256(_mm_setr_ps(d[0], d[1], d[2], 1.0f));  // lanes 4..7 unused
    const __m256 numerator = _mm256_permutevar8x32_ps(dir1, load_index(kNumeratorLanes[kz][flip]));
    const __m256 denominator = _mm256_permutevar8x32_ps(dir1, load_index(kDenominatorLanes[kz]));
    const __m256 q = _mm256_div_ps(numerator, denominator);  // 1/dir (+-inf for +-0), sx, sy, sz, 1, 1
    const auto lane = [&](int l) { return V8{_mm256_permutevar8x32_ps(q, _mm256_set1_epi32(l))}; };
    box.set(ray, lane(0), lane(1), lane(2));
    return simd::BlockRay<kLeafWidth>(kx, ky, kz, ray.org, lane(3), lane(4), lane(5));
#else
    alignas(32) const float numerator[8] = {1.0f, 1.0f, 1.0f, d[kx], d[ky], 1.0f, 1.0f, 1.0f};
    alignas(32) const float denominator[8] = {d[0], d[1], d[2], d[kz], d[kz], d[kz], 1.0f, 1.0f};
    alignas(32) float q[8];
    (V8::load(numerator) / V8::load(denominator)).store(q);  // 1/dir (+-inf for +-0), sx, sy, sz
    box.set(ray, q);
    return simd::BlockRay<kLeafWidth>(kx, ky, kz, ray.org, q[3], q[4], q[5]);
#endif
  }
};

struct StackEntry {
  std::uint32_t ref;
  float t_near;
};

/// Closest-hit state; the leaf test updates it.
struct ClosestHit {
  float t;
  float u = 0, v = 0;
  std::uint32_t triangle = kInvalidId;
};

/// Returns the first child of `node` in `lanes` (tree order) and pushes the others, in order, on the
/// stack at stack[sp], so that the last one is popped first. Writes up to eight entries past the
/// new top (the stack has that much slack). `lanes` must be non-zero.
inline std::uint32_t descend_and_push(const bvh::Node8& node, simd::LaneBits lanes, std::uint32_t* stack, int& sp) {
#if defined(__AVX512VL__)
  // Compress in a register and store all eight lanes at once: a per-child loop would have its trip
  // count mispredicted at almost every node.
  const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
  const __m256i hit = _mm256_maskz_compress_epi32(static_cast<__mmask8>(lanes), children);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack + sp), _mm256_alignr_epi32(hit, hit, 1));
  sp += std::popcount(lanes) - 1;
  return static_cast<std::uint32_t>(_mm256_cvtsi256_si32(hit));
#else
  const std::uint32_t first = node.child[simd::first_lane(lanes)];
  for (lanes &= lanes - 1; lanes != 0; lanes &= lanes - 1) stack[sp++] = node.child[simd::first_lane(lanes)];
  return first;
#endif
}

// Any hit: children are visited in tree order, without sorting and without distances on the stack.
// Measured on AO rays (bun_zipper, sponza, conference), near-to-far orders (sorted by entry
// distance, or by the split planes) were slower: the first occluder found ends the query, and the
// subtrees nearest the origin are often the surface the ray leaves.
bool occluded_traversal(const Bvh::Impl& bvh, const Ray& ray) {
  if (bvh.nodes.empty()) return false;
  const TraversalRay traversal_ray(ray);
  const bvh::BoxRay& box = traversal_ray.box;
  const LeafLanes tri_tmin = LeafLanes::broadcast(ray.tmin), tri_tmax = LeafLanes::broadcast(ray.tmax);
  const V8 box_tmin = V8::broadcast(widen_down(ray.tmin)), box_tmax = V8::broadcast(widen_up(ray.tmax));

  std::array<std::uint32_t, kStackSize + 8> stack;
  int sp = 0;
  const bvh::Node8* const nodes = bvh.nodes.data();
  std::uint32_t ref = bvh::node_ref(0);
  for (;;) {
    if (!bvh::is_leaf(ref)) {
      const bvh::Node8& node = bvh::node_at(nodes, ref);
      V8 t_near;
      simd::LaneBits lanes = bvh::test_children(node, box, box_tmin, box_tmax, t_near);
      if (lanes != 0) {
        ref = descend_and_push(node, lanes, stack.data(), sp);
        continue;
      }
    } else {
      const std::uint32_t first_block = bvh::leaf_first_block(ref);
      const std::uint32_t end_block = first_block + bvh::leaf_block_count(ref);
      for (std::uint32_t b = first_block; b != end_block; ++b) {
        if (simd::intersect_block<kLeafWidth, false>(bvh.blocks[b], traversal_ray.triangle, tri_tmin, tri_tmax,
                                                     nullptr) != 0)
          return true;
      }
    }
    if (sp == 0) return false;
    ref = stack[--sp];
  }
}

// Closest hit: children are visited near to far, and subtrees whose entry distance exceeds the
// closest hit so far are skipped.
bool closest_traversal(const Bvh::Impl& bvh, const Ray& ray, ClosestHit& best) {
  if (bvh.nodes.empty()) return false;
  const TraversalRay traversal_ray(ray);
  const bvh::BoxRay& box = traversal_ray.box;
  const simd::BlockRay<kLeafWidth>& tri_ray = traversal_ray.triangle;
  const LeafLanes tri_tmin = LeafLanes::broadcast(ray.tmin);
  LeafLanes tri_tmax = LeafLanes::broadcast(ray.tmax);
  const V8 box_tmin = V8::broadcast(widen_down(ray.tmin));
  float cull_t = widen_up(ray.tmax);
  V8 box_tmax = V8::broadcast(cull_t);
  best.t = ray.tmax;

  std::array<StackEntry, kStackSize> stack;
  int sp = 0;
  const bvh::Node8* const nodes = bvh.nodes.data();
  std::uint32_t ref = bvh::node_ref(0);  // the root
  for (;;) {
    if (!bvh::is_leaf(ref)) {
      const bvh::Node8& node = bvh::node_at(nodes, ref);
      V8 t_near;
      simd::LaneBits lanes = bvh::test_children(node, box, box_tmin, box_tmax, t_near);
      if (lanes != 0) {
        alignas(32) float dist[8];
        t_near.store(dist);
        const int first = simd::first_lane(lanes);
        lanes &= lanes - 1;
        if (lanes == 0) {
          ref = node.child[first];
          continue;
        }
        const int second = simd::first_lane(lanes);
        lanes &= lanes - 1;
        if (lanes == 0) {
          // Two children: descend into the nearer, push the farther.
          const bool swap = dist[second] < dist[first];
          const int near = swap ? second : first, far = swap ? first : second;
          stack[sp++] = {node.child[far], dist[far]};
          ref = node.child[near];
          continue;
        }
        // Three or more: sort by entry distance, push far to near, descend into the nearest.
        StackEntry hits[8];
        hits[0] = {node.child[first], dist[first]};
        hits[1] = {node.child[second], dist[second]};
        int count = 2;
        for (; lanes != 0; lanes &= lanes - 1) {
          const int l = simd::first_lane(lanes);
          hits[count++] = {node.child[l], dist[l]};
        }
        for (int i = 1; i < count; ++i) {
          const StackEntry e = hits[i];
          int j = i;
          for (; j > 0 && hits[j - 1].t_near > e.t_near; --j) hits[j] = hits[j - 1];
          hits[j] = e;
        }
        for (int i = count - 1; i > 0; --i) stack[sp++] = hits[i];
        ref = hits[0].ref;
        continue;
      }
    } else {
      const std::uint32_t first_block = bvh::leaf_first_block(ref);
      const std::uint32_t end_block = first_block + bvh::leaf_block_count(ref);
      for (std::uint32_t b = first_block; b != end_block; ++b) {
        simd::BlockHits<kLeafWidth> hits;
        simd::LaneBits lanes =
            simd::intersect_block<kLeafWidth, true>(bvh.blocks[b], tri_ray, tri_tmin, tri_tmax, &hits);
        if (lanes == 0) continue;
        for (; lanes != 0; lanes &= lanes - 1) {
          const int l = simd::first_lane(lanes);
          const std::uint32_t triangle = bvh.lane_triangle[b * kLeafWidth + static_cast<std::uint32_t>(l)];
          // hits.t[l] <= best.t here (best.t is the test's tmax); equal t: lowest index wins.
          if (hits.t[l] < best.t || (hits.t[l] == best.t && triangle < best.triangle))
            best = {hits.t[l], hits.u[l], hits.v[l], triangle};
        }
        tri_tmax = LeafLanes::broadcast(best.t);
        cull_t = widen_up(best.t);
        box_tmax = V8::broadcast(cull_t);
      }
    }
    // Next subtree from the stack that can still hold a hit.
    do {
      if (sp == 0) return best.triangle != kInvalidId;
      --sp;
    } while (stack[sp].t_near > cull_t);
    ref = stack[sp].ref;
  }
}

}  // namespace

std::optional<Hit> Bvh::Impl::intersect(const Ray& ray) const {
  ClosestHit best;
  if (!closest_traversal(*this, ray, best)) return std::nullopt;
  return Hit{best.t, best.u, best.v, prim[best.triangle], instance[best.triangle]};
}

bool Bvh::Impl::occluded(const Ray& ray) const { return occluded_traversal(*this, ray); }

}  // namespace vf
