#pragma once
/// \file Binned SAH construction of a binary BVH over boxes (build-only, private to the accel module):
/// triangles for the Bvh, object bounds for the instance layer's top level.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "visfield/accel/bvh.hpp"
#include "visfield/core/bounds.hpp"

namespace vf::bvh {

/// A node of the binary tree; a leaf when it has no children, then it covers
/// order[begin, begin + count) of its BinaryTree.
struct BinaryNode {
  Bounds3f bounds;
  std::unique_ptr<BinaryNode> left, right;
  std::uint32_t begin = 0, count = 0;

  bool is_leaf() const { return left == nullptr; }
};

/// The binary tree and the primitive order its leaves index into.
struct BinaryTree {
  std::unique_ptr<BinaryNode> root;  ///< Null when there are no boxes.
  std::vector<std::uint32_t> order;  ///< Box indices, grouped by leaf.
};

/// Builds the binary SAH tree over `boxes` (one per primitive, none empty): `config.bin_count` bins
/// over the centroid bounds of each node, leaf costs counted in blocks of `leaf_width` primitives,
/// leaves of at most config.max_leaf_size primitives, no leaf deeper than kMaxBinaryDepth. Parallel
/// over TBB's threads; the tree does not depend on the thread count.
BinaryTree build_binary_tree(std::span<const Bounds3f> boxes, const BvhConfig& config, int leaf_width);

}  // namespace vf::bvh
