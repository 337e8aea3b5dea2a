#pragma once
/// \file The oracle: tests every triangle for every ray. O(N) per ray; use for tests only.

#include <optional>
#include <string>
#include <vector>

#include "visfield/accel/accelerator.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

/// Exact reference structure: a copy of the triangles, no hierarchy. Ties in t are broken toward
/// the lowest triangle index of the TriangleSet. Thread-safe queries.
class BruteForce {
 public:
  /// Copies the triangles of `set`; O(N).
  static BruteForce build(const TriangleSet& set);
  /// Closest hit over all triangles.
  std::optional<Hit> intersect(const Ray& ray) const;
  /// True when any triangle is hit in [tmin, tmax].
  bool occluded(const Ray& ray) const;
  /// Build statistics.
  const AccelStats& stats() const { return stats_; }
  /// The --accel name, "brute".
  static std::string name() { return "brute"; }

 private:
  std::vector<std::array<Vec3f, 3>> triangles_;
  std::vector<std::uint32_t> prim_, instance_;
  AccelStats stats_;
};

}  // namespace vf
