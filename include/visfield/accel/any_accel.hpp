#pragma once
/// \file The one place that lists every exact structure: pick one by its --accel name at run time.
/// Adding a structure = one include and one entry in AnyAccel and build_accel.

#include <string>
#include <variant>
#include <vector>

#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/median_bsp.hpp"
#include "visfield/accel/uniform_grid.hpp"

namespace vf {

/// Any exact structure; use with std::visit so renderers stay generic.
using AnyAccel = std::variant<Bvh, UniformGrid, KdTree, MedianBsp, BruteForce>;

/// The --accel names build_accel accepts.
std::vector<std::string> accel_names();

/// Builds the structure named `name` over `set` with default parameters; throws vf::Error listing
/// the valid names when `name` is unknown. Records the build time in stats().build_ms.
AnyAccel build_accel(const std::string& name, const TriangleSet& set);

/// Build statistics of whichever structure `accel` holds.
AccelStats accel_stats(const AnyAccel& accel);

}  // namespace vf
