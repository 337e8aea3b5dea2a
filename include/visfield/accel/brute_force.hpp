#pragma once
/// \file The oracle: tests every triangle for every ray. O(N) per ray; use for tests only.

#include <memory>
#include <optional>
#include <string>

#include "visfield/accel/accelerator.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

/// Exact reference structure: a copy of the triangles, no hierarchy. Ties in t are broken toward
/// the lowest triangle index of the TriangleSet. Results (t, u, v, triangle) are bit-identical to
/// calling intersect_triangle() on every triangle in index order. Triangles are tested 16 (AVX-512),
/// 8 (AVX) or 4 at a time. Thread-safe queries. Move-only.
class BruteForce {
 public:
  /// Copies the triangles of `set`; O(N).
  static BruteForce build(const TriangleSet& set);
  BruteForce(BruteForce&&) noexcept;
  BruteForce& operator=(BruteForce&&) noexcept;
  ~BruteForce();

  /// Closest hit over all triangles.
  std::optional<Hit> intersect(const Ray& ray) const;
  /// True when any triangle is hit in [tmin, tmax].
  bool occluded(const Ray& ray) const;
  /// Build statistics.
  const AccelStats& stats() const;
  /// The --accel name, "brute".
  static std::string name() { return "brute"; }

  struct Impl;

 private:
  explicit BruteForce(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace vf
