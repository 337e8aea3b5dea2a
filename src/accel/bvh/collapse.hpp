#pragma once
/// \file Turns the binary SAH tree into the 8-wide node layout with SIMD leaf blocks (build-only).

#include "bvh/binary_builder.hpp"
#include "bvh/bvh_impl.hpp"

namespace vf::bvh {

/// Fills out.nodes, out.blocks and out.lane_triangle from `tree` (nodes and blocks in depth-first
/// order) and the node/leaf/reference/depth counts of out.stats. Each 8-wide node takes the two
/// children of a binary node and repeatedly replaces the interior child of largest surface area by
/// its two children while it has fewer than eight. O(nodes), serial.
void collapse_to_wide(const BinaryTree& tree, const TriangleSet& set, Bvh::Impl& out);

}  // namespace vf::bvh
