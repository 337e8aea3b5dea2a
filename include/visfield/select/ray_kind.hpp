#pragma once
/// \file The two ray distributions of the grids-vs-hierarchies experiments, and a set of queries
/// split into closest-hit rays and shadow (any-hit) rays.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "visfield/core/ray.hpp"

namespace vf {

/// Which rays a workload traces: the paper's "random rays" (segments between two random points of the
/// bounding sphere) or "path-tracing rays" (camera rays, diffuse bounces and shadow rays).
enum class RayKind { random, path };

/// Every ray kind, in the order calibration files and reports list them.
inline constexpr std::array<RayKind, 2> kRayKinds{RayKind::random, RayKind::path};

/// Index of `kind` in kRayKinds (0 or 1), for arrays indexed by kind.
constexpr std::size_t ray_kind_index(RayKind kind) { return kind == RayKind::random ? 0 : 1; }

/// "random" or "path": the name used on the command line and in calibration files.
std::string ray_kind_name(RayKind kind);

/// The kind named `name` ("random" or "path"), or nothing for any other text.
std::optional<RayKind> parse_ray_kind(std::string_view name);

/// Queries of one workload: rays answered by intersect() (closest hit) and rays answered by
/// occluded() (shadow rays). Plain value.
struct QuerySet {
  std::vector<Ray> closest;  ///< Closest-hit queries.
  std::vector<Ray> shadow;   ///< Any-hit (occlusion) queries.

  /// Total number of queries.
  std::size_t size() const { return closest.size() + shadow.size(); }
};

}  // namespace vf
