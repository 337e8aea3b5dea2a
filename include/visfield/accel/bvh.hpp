#pragma once
/// \file Exact SAH bounding volume hierarchy: binned SAH build (parallel, TBB), collapsed to an
/// 8-wide node layout with SIMD box tests, watertight triangle tests.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "visfield/accel/accelerator.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

/// Build parameters of the BVH; defaults are the ones measured fastest on the shared models.
struct BvhConfig {
  int bin_count = 32;               ///< SAH bins per axis.
  int max_leaf_size = 4;            ///< Leaves never hold more triangles than this (also the SIMD leaf width).
  float traversal_cost = 1.0f;      ///< SAH cost of visiting a node, relative to one triangle test.
  float intersection_cost = 1.0f;   ///< SAH cost of one triangle test.
};

/// An immutable 8-wide BVH over a TriangleSet. Queries are const and thread-safe. Move-only.
class Bvh {
 public:
  /// Builds over `set` (copied into leaf order); O(N log N), parallel over TBB's threads.
  static Bvh build(const TriangleSet& set, const BvhConfig& config = {});
  Bvh(Bvh&&) noexcept;
  Bvh& operator=(Bvh&&) noexcept;
  ~Bvh();

  /// Closest hit in [tmin, tmax]; same t and triangle as BruteForce except on exact ties.
  std::optional<Hit> intersect(const Ray& ray) const;
  /// True when any triangle is hit in [tmin, tmax]; stops at the first.
  bool occluded(const Ray& ray) const;
  /// Build statistics (node/leaf/reference counts, bytes, build ms).
  const AccelStats& stats() const;
  /// The --accel name, "bvh".
  static std::string name() { return "bvh"; }

  struct Impl;

 private:
  explicit Bvh(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace vf
