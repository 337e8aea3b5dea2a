#pragma once
/// \file The oracle: tests every triangle for every ray. O(N) per ray; use for tests only.

#include <memory>
#include <string>

#include "visfield/accel/query.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

namespace brute {
struct BruteLayout;
}

/// Exact reference structure: a copy of the triangles, no hierarchy; the definition every exact
/// structure is tested against. The closest hit is the first triangle in TriangleSet order whose
/// intersect_triangle() t is the smallest (ties go to the lowest index); t, u, v are bit-identical to
/// that test. Triangles are tested 16 (AVX-512), 8 (AVX) or 4 at a time. Thread-safe queries. Move-only.
class BruteForce {
 public:
  /// Copies the triangles of `set`; O(N).
  static BruteForce build(const TriangleSet& set);
  /// Bytes build() takes for `triangles` triangles: 48 per triangle (44 measured).
  static double estimate_build_bytes(std::size_t triangles) { return 48.0 * static_cast<double>(triangles); }
  BruteForce(BruteForce&&) noexcept;
  BruteForce& operator=(BruteForce&&) noexcept;
  ~BruteForce();

  /// Closest hit over all triangles.
  Hit intersect(const Ray& ray) const;
  /// True when any triangle is hit in (tmin, tmax].
  bool occluded(const Ray& ray) const;
  /// Build statistics.
  const AccelStats& stats() const;
  /// The registry name, "brute".
  static std::string name() { return "brute"; }
  static constexpr Exactness exactness = Exactness::exact;

 private:
  explicit BruteForce(std::unique_ptr<const brute::BruteLayout> layout);
  std::unique_ptr<const brute::BruteLayout> layout_;
};

}  // namespace vf
