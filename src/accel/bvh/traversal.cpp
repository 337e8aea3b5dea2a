// Single-ray traversal of the 8-wide triangle BVH: closest hit and any hit. Boxes are tested
// conservatively (box_test.hpp) and padded (collapse.cpp); leaves run the same block test as
// BruteForce, and among equal t the lowest TriangleSet index wins, so closest hits are the oracle's
// (ties included) whenever the triangle test's rounding keeps a computed hit inside the padded boxes.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <optional>
#include <span>

#include "bvh/box_test.hpp"
#include "bvh/bvh_layout.hpp"
#include "bvh/wide_traversal.hpp"

namespace vf::bvh {
namespace {

using LeafLanes = simd::Lanes<kLeafWidth>;

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
  BoxRay box;
  simd::BlockRay<kLeafWidth> triangle;

  explicit TraversalRay(const Ray& ray) : triangle(shear(ray, box)) {}

 private:
  static simd::BlockRay<kLeafWidth> shear(const Ray& ray, BoxRay& box) {
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

/// The leaves of the Bvh: runs of triangle blocks, tested with the oracle's kernel. With kCount, each
/// leaf and block tested is added to the counters.
template <bool kCount>
class TriangleLeaves {
 public:
  TriangleLeaves(const BvhLayout& bvh, const TraversalRay& ray, float tmin, float tmax, BvhQueryCounters* counters)
      : bvh_(bvh), ray_(ray.triangle), tmin_(LeafLanes::broadcast(tmin)), tmax_(LeafLanes::broadcast(tmax)), counters_(counters) {}

  /// Any triangle of leaf `ref` hit in (tmin, tmax].
  bool any(std::uint32_t ref) const {
    const std::uint32_t first = leaf_first_item(ref), end = first + leaf_item_count(ref);
    count_leaf();
    for (std::uint32_t b = first; b != end; ++b) {
      count_block(b);
      if (simd::intersect_block<kLeafWidth, false>(bvh_.blocks[b].triangles, ray_, tmin_, tmax_, nullptr) != 0) return true;
    }
    return false;
  }

  /// Tests leaf `ref` against [tmin, best_t]; true when it found a nearer hit (or an equally near one
  /// on a lower triangle index), which then becomes the best.
  bool closest(std::uint32_t ref, float& best_t) {
    const std::uint32_t first = leaf_first_item(ref), end = first + leaf_item_count(ref);
    bool improved = false;
    count_leaf();
    for (std::uint32_t b = first; b != end; ++b) {
      count_block(b);
      simd::BlockHits<kLeafWidth> hits;
      simd::LaneBits lanes = simd::intersect_block<kLeafWidth, true>(bvh_.blocks[b].triangles, ray_, tmin_, tmax_, &hits);
      if (lanes == 0) continue;
      for (; lanes != 0; lanes &= lanes - 1) {
        const int l = simd::first_lane(lanes);
        const std::uint32_t slot = b * kLeafWidth + static_cast<std::uint32_t>(l);
        const std::uint32_t triangle = bvh_.blocks[b].triangle[l];
        // hits.t[l] <= best_t here (best_t is the test's tmax); equal t: lowest index wins.
        if (hits.t[l] < best_t || (hits.t[l] == best_t && triangle < triangle_)) {
          best_t = hits.t[l];
          u_ = hits.u[l];
          v_ = hits.v[l];
          triangle_ = triangle;
          slot_ = slot;
          t_ = best_t;
          improved = true;
        }
      }
      tmax_ = LeafLanes::broadcast(best_t);
    }
    return improved;
  }

  /// The best hit closest() found, or a miss.
  Hit hit() const {
    if (triangle_ == kInvalidId) return Hit{};
    const LeafBlock& block = bvh_.blocks[slot_ / kLeafWidth];
    const int lane = static_cast<int>(slot_ % kLeafWidth);
    return Hit::triangle(t_, u_, v_, block.prim[lane], block.instance[lane], block.triangles.normal(lane));
  }

 private:
  void count_leaf() const {
    if constexpr (kCount) ++counters_->leaves;
  }
  void count_block(std::uint32_t b) const {
    if constexpr (kCount) {
      ++counters_->blocks;
      for (int lane = 0; lane < kLeafWidth; ++lane)
        counters_->triangle_tests += bvh_.blocks[b].triangle[lane] != kInvalidId ? 1 : 0;
    }
  }

  const BvhLayout& bvh_;
  const simd::BlockRay<kLeafWidth>& ray_;
  const LeafLanes tmin_;
  LeafLanes tmax_;
  BvhQueryCounters* counters_;
  float t_ = 0.0f, u_ = 0.0f, v_ = 0.0f;
  std::uint32_t triangle_ = kInvalidId, slot_ = 0;
};

template <bool kCount>
Hit closest_hit(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  if constexpr (kCount) ++counters->rays;
  if (bvh.nodes.empty()) return Hit{};
  const TraversalRay traversal_ray(ray);
  TriangleLeaves<kCount> leaves(bvh, traversal_ray, ray.tmin, ray.tmax, counters);
  const auto visit = [&](std::uint32_t ref, float& best_t) { return leaves.closest(ref, best_t); };
  if constexpr (kCount)
    closest_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, visit, [&] { ++counters->nodes; });
  else
    closest_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, visit);
  return leaves.hit();
}

template <bool kCount>
bool any_hit(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  if constexpr (kCount) ++counters->rays;
  if (bvh.nodes.empty()) return false;
  const TraversalRay traversal_ray(ray);
  const TriangleLeaves<kCount> leaves(bvh, traversal_ray, ray.tmin, ray.tmax, counters);
  const auto test = [&](std::uint32_t ref) { return leaves.any(ref); };
  if constexpr (kCount)
    return any_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, test, [&] { ++counters->nodes; });
  else
    return any_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, test);
}

}  // namespace

void occluded_stream(const BvhLayout& bvh, std::span<const Ray> rays, std::uint8_t* occluded) {
  if (bvh.nodes.empty()) {
    std::fill(occluded, occluded + rays.size(), std::uint8_t{0});
    return;
  }
  // One ray's walk is a chain of dependent loads and compares (a node's boxes, then the child they
  // pick); several rays' walks stepped in turn keep the core busy while each waits.
  struct Slot {
    std::optional<TraversalRay> ray;
    std::optional<TriangleLeaves<false>> leaves;
    AnyHitState walk;
    std::size_t index = 0;
    bool live = false;
  };
  std::array<Slot, kStreamWalks> slots;
  std::size_t next = 0;
  const auto start = [&](Slot& slot) {
    if (next == rays.size()) return false;
    const Ray& ray = rays[next];
    slot.ray.emplace(ray);
    slot.leaves.emplace(bvh, *slot.ray, ray.tmin, ray.tmax, nullptr);
    slot.walk.start(ray.tmin, ray.tmax);
    slot.index = next++;
    return true;
  };
  int live = 0;
  for (Slot& slot : slots) live += (slot.live = start(slot)) ? 1 : 0;
  while (live > 0) {
    for (Slot& slot : slots) {
      if (!slot.live) continue;
      const AnyHitState::Step step = slot.walk.step(
          bvh.nodes.data(), slot.ray->box, [&](std::uint32_t ref) { return slot.leaves->any(ref); }, IgnoreNodes{});
      if (step == AnyHitState::Step::going) continue;
      occluded[slot.index] = step == AnyHitState::Step::hit ? 1 : 0;
      if (!(slot.live = start(slot))) --live;
    }
  }
}

void intersect_stream(const BvhLayout& bvh, std::span<const Ray> rays, Hit* hits) {
  if (bvh.nodes.empty()) {
    std::fill(hits, hits + rays.size(), Hit{});
    return;
  }
  // As occluded_stream: several rays' walks stepped in turn.
  struct Slot {
    std::optional<TraversalRay> ray;
    std::optional<TriangleLeaves<false>> leaves;
    ClosestHitState walk;
    std::size_t index = 0;
    bool live = false;
  };
  std::array<Slot, kClosestStreamWalks> slots;
  std::size_t next = 0;
  const auto start = [&](Slot& slot) {
    if (next == rays.size()) return false;
    const Ray& ray = rays[next];
    slot.ray.emplace(ray);
    slot.leaves.emplace(bvh, *slot.ray, ray.tmin, ray.tmax, nullptr);
    slot.walk.start(ray.tmin, ray.tmax);
    slot.index = next++;
    return true;
  };
  int live = 0;
  for (Slot& slot : slots) live += (slot.live = start(slot)) ? 1 : 0;
  while (live > 0) {
    for (Slot& slot : slots) {
      if (!slot.live) continue;
      const auto visit = [&](std::uint32_t ref, float& best_t) { return slot.leaves->closest(ref, best_t); };
      if (slot.walk.step(bvh.nodes.data(), slot.ray->box, visit, IgnoreNodes{})) continue;
      std::construct_at(&hits[slot.index], slot.leaves->hit());
      if (!(slot.live = start(slot))) --live;
    }
  }
}

Hit intersect(const BvhLayout& bvh, const Ray& ray) { return closest_hit<false>(bvh, ray, nullptr); }
bool occluded(const BvhLayout& bvh, const Ray& ray) { return any_hit<false>(bvh, ray, nullptr); }
Hit intersect(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) { return closest_hit<true>(bvh, ray, counters); }
bool occluded(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) { return any_hit<true>(bvh, ray, counters); }

}  // namespace vf::bvh
