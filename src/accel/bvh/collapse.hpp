#pragma once
/// \file Turns a binary SAH tree into 8-wide nodes (build-only, private to the accel module).

#include <cstdint>
#include <functional>

#include "bvh/binary_builder.hpp"
#include "bvh/wide_nodes.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/accel/query.hpp"

namespace vf::bvh {

/// Writes the items of one binary leaf wherever the tree's owner keeps them and returns the leaf's
/// child reference (leaf_ref(first, count)).
using LeafWriter = std::function<std::uint32_t(const BinaryNode& leaf)>;

/// Fills `nodes` from `tree` (depth-first; nodes[0] is the root, even when the root is a leaf) and
/// the node, leaf and depth counts of `stats`, calling `write_leaf` for every leaf in depth-first
/// order. Each 8-wide node takes the two children of a binary node and repeatedly replaces the
/// interior child of largest surface area by its two children while it has fewer than eight. Child
/// boxes are grown by a small margin (see collapse.cpp). O(nodes), serial. Throws vf::Error when the
/// tree needs more than kMaxNodes nodes.
void collapse_to_wide(const BinaryTree& tree, AlignedVector<Node8>& nodes, AccelStats& stats,
                      const LeafWriter& write_leaf);

}  // namespace vf::bvh
