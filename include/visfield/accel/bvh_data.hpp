#pragma once
/// \file The SAH BVH as plain data, apart from any traversal layout (as madmann91/bvh keeps the
/// structure data and its builder apart): 8-wide nodes holding their children's boxes, and leaves as
/// runs of triangle indices. Bvh builds the same tree into its own SIMD layout; the GPU layout
/// (gpu/gpu_bvh.hpp) is made from this, as a serialisation would be.

#include <array>
#include <cstdint>
#include <vector>

#include "visfield/accel/bvh.hpp"
#include "visfield/accel/query.hpp"
#include "visfield/core/bounds.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

/// One child slot of a WideBvhNode.
struct WideBvhChild {
  enum class Kind : std::uint8_t { empty, node, leaf };
  Kind kind = Kind::empty;
  Bounds3f bounds;          ///< The child's box, grown as Bvh grows it for the watertight test.
  std::uint32_t index = 0;  ///< node: its index in WideBvhData::nodes; leaf: its first entry of WideBvhData::triangles.
  std::uint32_t count = 0;  ///< leaf: its triangles (1..16).
};

/// An 8-wide node: its children in slot order (Bvh visits them in this order for any hit).
struct WideBvhNode {
  std::array<WideBvhChild, 8> children;
};

/// A whole tree as data.
struct WideBvhData {
  std::vector<WideBvhNode> nodes;        ///< nodes[0] is the root (a root leaf sits in one slot of it); none for an empty set.
  std::vector<std::uint32_t> triangles;  ///< TriangleSet indices, leaf after leaf.
  AccelStats stats;                      ///< Nodes, leaves, depth (8-wide levels), build time.
};

/// The tree Bvh's builder makes over `set`'s triangles (binned SAH with `config`'s bins, leaves of at
/// most config.max_leaf_size triangles in [1, 16], collapsed to 8-wide nodes with grown boxes), as data.
/// `leaf_cost_width`: the SAH counts a leaf's cost in blocks of this many triangles (Bvh: 8, its SIMD
/// width; 1: a test a triangle, as a GPU thread tests them). O(N log N), parallel over TBB's threads;
/// the result does not depend on the thread count. Throws vf::Error on a bad config.
WideBvhData build_wide_bvh(const TriangleSet& set, const BvhConfig& config = {}, int leaf_cost_width = 8);

}  // namespace vf
