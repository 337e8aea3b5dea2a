#pragma once
/// \file Spatial-median BSP: the "CRT" baseline of VLF-RT (Wald & Slusallek's coherent ray tracing
/// kd-tree with spatial-median planes). Every node is cut in the middle of its longest axis (ties:
/// x before y before z; this adapts to elongated scenes, which round-robin axes would not);
/// triangles crossing the plane go to both children with their clipped bounds. Same 8-byte nodes
/// and the same traversal as KdTree.

#include <memory>
#include <string>

#include "visfield/accel/query.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

namespace kd {
struct KdLayout;
}

/// Build parameters of the median BSP. A node becomes a leaf when it holds at most max_leaf_size
/// triangles, at max_depth, or when its box is too thin to be halved in float. Spatial-median trees
/// do not adapt to the geometry, so deep trees multiply the references of large triangles; the
/// defaults were measured fastest on AO rays over the shared models (VLF-RT tuned its CRT baseline
/// per scene, at depths 16 to 23).
struct MedianBspConfig {
  int max_depth = 0;       ///< Most splits above a leaf, in [1, 64]; 0 = automatic, round(log2 N).
  int max_leaf_size = 8;   ///< Nodes with more triangles are split (until max_depth); >= 1.
};

/// An immutable spatial-median BSP over a TriangleSet. Queries are const and thread-safe. Move-only.
class MedianBsp {
 public:
  /// Builds over `set`; O(N depth), parallel over TBB's threads, the same tree for any thread count.
  /// Throws vf::Error on a bad config or when the tree outgrows its 32-bit node fields.
  static MedianBsp build(const TriangleSet& set, const MedianBspConfig& config = {});
  /// Peak bytes build() takes for `triangles` triangles when references stay near 2 per triangle:
  /// 256 per triangle (measured 105 on Armadillo). Duplication beyond that (2300 bytes per triangle
  /// on a soup of large triangles) is checked as the tree grows (build throws past the memory limit).
  static double estimate_build_bytes(std::size_t triangles, const MedianBspConfig& config = {});
  MedianBsp(MedianBsp&&) noexcept;
  MedianBsp& operator=(MedianBsp&&) noexcept;
  ~MedianBsp();

  /// Closest hit in (tmin, tmax]; bit-identical to BruteForce (ties: lowest triangle index).
  Hit intersect(const Ray& ray) const;
  /// True when any triangle is hit in (tmin, tmax]; stops at the first.
  bool occluded(const Ray& ray) const;
  /// Build statistics, counted as for KdTree::stats().
  const AccelStats& stats() const;
  /// The registry name, "median-bsp".
  static std::string name() { return "median-bsp"; }
  static constexpr Exactness exactness = Exactness::exact;

 private:
  explicit MedianBsp(std::unique_ptr<const kd::KdLayout> layout);
  std::unique_ptr<const kd::KdLayout> layout_;
};

}  // namespace vf
