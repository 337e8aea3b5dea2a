#pragma once
/// \file What every ray–scene query structure provides: the Accelerator concept and build statistics.

#include <concepts>
#include <cstddef>
#include <optional>
#include <string>

#include "visfield/core/ray.hpp"

namespace vf {

/// Build statistics every structure reports.
struct AccelStats {
  double build_ms = 0.0;            ///< Wall-clock build time in milliseconds.
  std::size_t memory_bytes = 0;     ///< Bytes held by the built structure (triangle copies included).
  std::size_t node_count = 0;       ///< Interior nodes (or cells).
  std::size_t leaf_count = 0;       ///< Leaves (or non-empty cells).
  std::size_t reference_count = 0;  ///< Triangle references stored in leaves.
  int max_depth = 0;                ///< Deepest leaf.
};

/// A built, immutable structure answering ray queries over a TriangleSet. Queries are const and
/// thread-safe; hits satisfy tmin <= t <= tmax and carry (prim, instance) of the scene triangle.
template <class A>
concept Accelerator = requires(const A& a, const Ray& ray) {
  { a.intersect(ray) } -> std::same_as<std::optional<Hit>>;  ///< Closest hit, if any.
  { a.occluded(ray) } -> std::same_as<bool>;                  ///< Any hit in [tmin, tmax].
  { a.stats() } -> std::convertible_to<AccelStats>;
  { A::name() } -> std::convertible_to<std::string>;          ///< The --accel name.
};

}  // namespace vf
