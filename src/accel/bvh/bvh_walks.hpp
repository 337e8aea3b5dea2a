#pragma once
/// \file The Bvh's per-ray walks (private to the accel module): the ray's constants, the leaves'
/// block tests, and a resumable any-hit walk that streams of rays step in turn (the Bvh's own
/// occluded_stream, the instance layer's objects).

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>

#include "bvh/box_test.hpp"
#include "bvh/bvh_layout.hpp"
#include "bvh/wide_traversal.hpp"

#ifndef VISFIELD_MEASURE_BVH_CUT
#define VISFIELD_MEASURE_BVH_CUT 0
#endif

namespace vf::bvh {

/// A measurement build's cut (CMake VISFIELD_MEASURE_BVH_CUT; 0 in every other build): 1 and 2 take
/// parts out of the Bvh's closest-hit stream, 3 the objects out of the instance layer's any-hit
/// stream. Internal linkage: only the sources CMake names see the option's value.
constexpr int kMeasureCut = VISFIELD_MEASURE_BVH_CUT;

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

  /// The triangle test's constants alone (those of TraversalRay(ray).triangle, bit for bit), for
  /// rays that meet no box.
  static simd::BlockRay<kLeafWidth> triangle_ray(const Ray& ray) {
    BoxRay unused;  // a local never read: the compiler drops its stores
    return shear(ray, unused);
  }

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
    // The operands are gathered by register permutes: building them in a stack array with scalar
    // stores and reloading it as a vector stalls on store forwarding, which measured as a sixth of a
    // short AO traversal. (The other way, one vector store read back as scalars, forwards.)
    const int flip = swap != 0 ? 1 : 0;
    const __m256 dir1 = _mm256_castps128_ps256(_mm_setr_ps(d[0], d[1], d[2], 1.0f));  // lanes 4..7 unused
    const __m256 numerator = _mm256_permutevar8x32_ps(dir1, load_index(kNumeratorLanes[kz][flip]));
    const __m256 denominator = _mm256_permutevar8x32_ps(dir1, load_index(kDenominatorLanes[kz]));
    const __m256 q = _mm256_div_ps(numerator, denominator);  // 1/dir (+-inf for +-0), sx, sy, sz, 1, 1
    alignas(32) float quotients[8];
    _mm256_store_ps(quotients, q);
#else
    alignas(32) const float numerator[8] = {1.0f, 1.0f, 1.0f, d[kx], d[ky], 1.0f, 1.0f, 1.0f};
    alignas(32) const float denominator[8] = {d[0], d[1], d[2], d[kz], d[kz], d[kz], 1.0f, 1.0f};
    alignas(32) float quotients[8];
    (V8::load(numerator) / V8::load(denominator)).store(quotients);  // 1/dir (+-inf for +-0), sx, sy, sz
#endif
    box.set(ray, quotients);
    const float o[3] = {ray.org.x, ray.org.y, ray.org.z};  // indexed without Vec3f's branches
    return simd::BlockRay<kLeafWidth>(kx, ky, kz, o[kx], o[ky], o[kz], quotients[3], quotients[4], quotients[5]);
  }
};

/// The leaves of a Bvh: runs of triangle blocks, tested with the oracle's kernel. With kCount, each
/// leaf and block tested is added to the counters.
template <bool kCount>
class TriangleLeaves {
 public:
  TriangleLeaves(const BvhLayout& bvh, const TraversalRay& ray, float tmin, float tmax, BvhQueryCounters* counters)
      : TriangleLeaves(bvh, ray.triangle, tmin, tmax, counters) {}
  /// The leaves for a ray of which only the triangle test's constants are known (`ray` must outlive them).
  TriangleLeaves(const BvhLayout& bvh, const simd::BlockRay<kLeafWidth>& ray, float tmin, float tmax, BvhQueryCounters* counters)
      : bvh_(bvh), ray_(ray), tmin_(LeafLanes::broadcast(tmin)), tmax_(LeafLanes::broadcast(tmax)), counters_(counters) {}

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

/// A direct Bvh's closest hit (see BvhLayout::direct): every block tested, no box.
template <bool kCount>
Hit closest_hit_direct(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  const simd::BlockRay<kLeafWidth> triangle_ray = TraversalRay::triangle_ray(ray);
  TriangleLeaves<kCount> leaves(bvh, triangle_ray, ray.tmin, ray.tmax, counters);
  float best_t = ray.tmax;
  leaves.closest(bvh.all_blocks(), best_t);
  return leaves.hit();
}

/// A direct Bvh's any hit (see BvhLayout::direct): every block tested, no box.
template <bool kCount>
bool any_hit_direct(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  const simd::BlockRay<kLeafWidth> triangle_ray = TraversalRay::triangle_ray(ray);
  return TriangleLeaves<kCount>(bvh, triangle_ray, ray.tmin, ray.tmax, counters).any(bvh.all_blocks());
}

/// How many rays' constants with_traversal_rays() computes at a time.
inline constexpr std::size_t kTraversalRun = 64;

/// Calls run(first, count, traversal_rays) for consecutive runs of `rays`, with the runs' rays' constants
/// computed beforehand in one loop: each ray's set-up is a chain of dependent steps (its largest
/// axis, a table lookup, a division, permutes) that a loop of independent rays overlaps, where a
/// walk started between other walks' steps would wait for it.
template <class Run>
void with_traversal_rays(std::span<const Ray> rays, Run&& run) {
  std::array<std::optional<TraversalRay>, kTraversalRun> traversal_rays;
  for (std::size_t first = 0; first < rays.size(); first += kTraversalRun) {
    const std::size_t count = std::min(kTraversalRun, rays.size() - first);
    for (std::size_t i = 0; i < count; ++i) traversal_rays[i].emplace(rays[first + i]);
    run(first, count, traversal_rays.data());
  }
}

/// One ray's any-hit walk through a Bvh, taken a node or leaf at a time.
class BvhAnyHit {
 public:
  /// A walk of `ray` through `bvh` (which must outlive it), from the root.
  void start(const BvhLayout& bvh, const Ray& ray) {
    if (bvh.nodes.empty() || !ray.is_valid()) {
      nodes_ = nullptr;
      return;
    }
    own_ray_.emplace(ray);
    start(bvh, ray, *own_ray_);
  }
  /// As above, with the ray's constants computed beforehand (`traversal_ray` must outlive the walk).
  void start(const BvhLayout& bvh, const Ray& ray, const TraversalRay& traversal_ray) {
    nodes_ = bvh.nodes.empty() || !ray.is_valid() ? nullptr : bvh.nodes.data();  // an invalid ray misses at once
    if (!nodes_) return;
    ray_ = &traversal_ray;
    leaves_.emplace(bvh, traversal_ray, ray.tmin, ray.tmax, nullptr);
    walk_.start(ray.tmin, ray.tmax);
  }
  /// The next node or leaf; an empty Bvh misses at once.
  AnyHitState::Step step() {
    if (!nodes_) return AnyHitState::Step::miss;
    return walk_.step(nodes_, ray_->box, [&](std::uint32_t ref) { return leaves_->any(ref); }, IgnoreNodes{});
  }

 private:
  const Node8* nodes_ = nullptr;
  std::optional<TraversalRay> own_ray_;
  const TraversalRay* ray_ = nullptr;
  std::optional<TriangleLeaves<false>> leaves_;
  AnyHitState walk_;
};

}  // namespace vf::bvh
