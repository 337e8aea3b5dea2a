#pragma once
/// \file A workload's queries, split by role: closest-hit rays and occlusion (shadow) rays.

#include <cstddef>
#include <vector>

#include "visfield/core/ray.hpp"

namespace vf {

/// Queries of one workload: rays answered by intersect() (closest hit) and rays answered by
/// occluded() (shadow rays). Plain value.
struct QuerySet {
  std::vector<Ray> closest;  ///< Closest-hit queries.
  std::vector<Ray> shadow;   ///< Any-hit (occlusion) queries.

  /// Total number of queries.
  std::size_t size() const { return closest.size() + shadow.size(); }
};

}  // namespace vf
