#pragma once
/// \file Where the experiments' casters stand: a mesh scaled to a bounding-sphere radius and stood on
/// the floor y = 0, as the papers place their casters.

#include "visfield/core/transform.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::experiments {

/// Where a caster stands: its bounding sphere's radius and its centre's position (x, z) on the floor y = 0.
struct Placement {
  float radius, x, z;
};

/// The object transform that scales the mesh of `set` (non-empty) to `placement.radius` and stands it
/// on y = 0 with its bounding sphere's centre above (x, z).
Transform standing_transform(const TriangleSet& set, const Placement& placement);

}  // namespace vf::experiments
