#pragma once
/// \file Exact SAH bounding volume hierarchy: binned SAH build (parallel, TBB), collapsed to an
/// 8-wide node layout with SIMD box tests, leaves of 8-triangle SIMD blocks tested with the
/// oracle's watertight kernel.

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "visfield/accel/query.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

namespace bvh {
struct BvhLayout;
}
class InstanceLayer;

/// Build parameters of the BVH; defaults are the ones measured fastest on the shared models (AO
/// rays on bun_zipper, sponza, conference). Bvh::build throws vf::Error on values out of range.
struct BvhConfig {
  int bin_count = 32;               ///< SAH bins per axis, in [2, 64]; a range of n triangles uses min(bin_count, 4 + n / 20).
  int max_leaf_size = 8;            ///< Leaves never hold more triangles than this, in [1, 128].
  float traversal_cost = 1.0f;      ///< SAH cost of visiting a node, relative to one leaf block test (>= 0).
  float intersection_cost = 1.0f;   ///< SAH cost of one leaf block test (8 triangles at once; > 0).
};

/// Work done by Bvh queries, summed over the rays of counting queries (for finding where the time
/// goes). Plain value; not thread-safe (use one per thread and add them up).
struct BvhQueryCounters {
  std::uint64_t rays = 0;            ///< Queries counted.
  std::uint64_t nodes = 0;           ///< 8-wide interior nodes whose children's boxes were tested.
  std::uint64_t leaves = 0;          ///< Leaves visited.
  std::uint64_t blocks = 0;          ///< 8-triangle blocks tested.
  std::uint64_t triangle_tests = 0;  ///< Triangles in the blocks tested (lanes holding one).

  /// Adds `o` to this.
  BvhQueryCounters& operator+=(const BvhQueryCounters& o) {
    rays += o.rays, nodes += o.nodes, leaves += o.leaves, blocks += o.blocks, triangle_tests += o.triangle_tests;
    return *this;
  }
};

/// An immutable 8-wide BVH over a TriangleSet. Queries are const and thread-safe. Move-only.
class Bvh {
 public:
  /// Builds over `set` (copied into leaf order); O(N log N), parallel over TBB's threads. The tree does
  /// not depend on the thread count. Throws vf::Error on a bad config or more than 2^27 - 1 triangles.
  static Bvh build(const TriangleSet& set, const BvhConfig& config = {});
  /// Peak bytes build() takes for `triangles` triangles (boxes, order, binary tree, result): 128 per
  /// triangle, above the 95 measured on a 1M-triangle soup and 83 on Armadillo (docs/hardening.md).
  static double estimate_build_bytes(std::size_t triangles, const BvhConfig& config = {});
  Bvh(Bvh&&) noexcept;
  Bvh& operator=(Bvh&&) noexcept;
  ~Bvh();

  /// Closest hit in (tmin, tmax], with the triangle's geometric normal: the same t, u, v and triangle
  /// as BruteForce (equal t: the lowest TriangleSet index) provided the triangle test's rounding keeps
  /// its computed hit inside the node boxes, which are padded by 2^-16 of their extent for that
  /// purpose (it has held on every ray of the differential tests).
  Hit intersect(const Ray& ray) const;
  /// True when any triangle is hit in (tmin, tmax]; stops at the first.
  bool occluded(const Ray& ray) const;
  /// intersect(ray), adding its work to `counters` (a traversal of its own, so the plain query pays nothing).
  Hit intersect(const Ray& ray, BvhQueryCounters& counters) const;
  /// occluded(ray), adding its work to `counters`.
  bool occluded(const Ray& ray, BvhQueryCounters& counters) const;
  /// Build statistics: 8-wide node count, leaf count, triangle references, deepest leaf (in 8-wide
  /// levels), bytes (nodes, leaf blocks, lane and id maps), build ms.
  const AccelStats& stats() const;
  /// The registry name, "bvh".
  static std::string name() { return "bvh"; }
  static constexpr Exactness exactness = Exactness::exact;

 private:
  friend void occluded_block(const Bvh&, std::span<const Ray>, std::span<std::uint8_t>);
  friend void intersect_batch(const Bvh&, std::span<const Ray>, std::span<Hit>);
  friend void occluded_block(const InstanceLayer&, std::span<const Ray>, std::span<std::uint8_t>);
  explicit Bvh(std::unique_ptr<const bvh::BvhLayout> layout);
  std::unique_ptr<const bvh::BvhLayout> layout_;
};

/// occluded[i] = bvh.occluded(rays[i]) for every i (spans of equal size), bit for bit, on the calling
/// thread (for callers already parallel, such as a renderer's tiles): several rays' walks stepped in
/// turn, so that one ray's wait for memory and compares overlaps another's work.
void occluded_block(const Bvh& bvh, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// occluded_block() over chunks of the rays in parallel (TBB); the same answers. Throws
/// vf::Interrupted on a signal.
void occluded_batch(const Bvh& bvh, std::span<const Ray> rays, std::span<std::uint8_t> occluded);

/// hits[i] = bvh.intersect(rays[i]) for every i (spans of equal size), bit for bit: chunks of the rays
/// in parallel (TBB), several rays' walks stepped in turn in each. Throws vf::Interrupted on a signal.
void intersect_batch(const Bvh& bvh, std::span<const Ray> rays, std::span<Hit> hits);

}  // namespace vf
