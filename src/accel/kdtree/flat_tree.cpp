#include "kdtree/flat_tree.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "visfield/core/error.hpp"

namespace vf::kd {
namespace {

void check_node_count(std::size_t count) {
  if (count > std::size_t{kMaxNodePayload} + 1)
    throw Error("kd-tree build: more than " + std::to_string(kMaxNodePayload + 1) +
                " nodes; lower max_depth or raise the leaf size");
}

void check_reference_count(std::size_t count) {
  if (count > std::numeric_limits<std::uint32_t>::max())
    throw Error("kd-tree build: more than 2^32 - 1 triangle references; lower max_depth or raise the leaf size");
}

}  // namespace

void FlatTree::add_leaf(std::span<const std::uint32_t> triangles, int depth) {
  if (triangles.size() > kMaxNodePayload)
    throw Error("kd-tree build: a leaf would hold " + std::to_string(triangles.size()) + " triangles, more than " +
                std::to_string(kMaxNodePayload));
  check_reference_count(references.size() + triangles.size());
  check_node_count(nodes.size() + 1);
  nodes.push_back(KdNode::leaf(static_cast<std::uint32_t>(references.size()), static_cast<std::uint32_t>(triangles.size())));
  references.insert(references.end(), triangles.begin(), triangles.end());
  ++leaf_count;
  max_depth = std::max(max_depth, depth + 1);
}

std::size_t FlatTree::begin_interior() {
  check_node_count(nodes.size() + 1);
  nodes.emplace_back();
  ++interior_count;
  return nodes.size() - 1;
}

void FlatTree::end_interior(std::size_t index, int axis, float split) {
  check_node_count(nodes.size() + 1);
  nodes[index] = KdNode::interior(axis, split, static_cast<std::uint32_t>(nodes.size()));
}

void FlatTree::append(const FlatTree& subtree) {
  check_node_count(nodes.size() + subtree.nodes.size());
  check_reference_count(references.size() + subtree.references.size());
  const auto node_base = static_cast<std::uint32_t>(nodes.size());
  const auto reference_base = static_cast<std::uint32_t>(references.size());
  nodes.reserve(nodes.size() + subtree.nodes.size());
  for (const KdNode& n : subtree.nodes)
    nodes.push_back(n.is_leaf() ? KdNode::leaf(n.leaf_first() + reference_base, n.leaf_count())
                                : KdNode::interior(n.axis(), n.split(), n.right_child() + node_base));
  references.insert(references.end(), subtree.references.begin(), subtree.references.end());
  interior_count += subtree.interior_count;
  leaf_count += subtree.leaf_count;
  max_depth = std::max(max_depth, subtree.max_depth);
}

void finish_layout(FlatTree&& tree, const TriangleSet& set, KdLayout& layout) {
  layout.nodes = std::move(tree.nodes);
  // Leaf i's blocks start at the sum of the block counts of the leaves before it; its references
  // start at first_reference[i].
  std::vector<std::uint32_t> first_reference(layout.nodes.size(), 0);
  std::size_t block_total = 0;
  for (std::size_t i = 0; i < layout.nodes.size(); ++i) {
    KdNode& node = layout.nodes[i];
    if (!node.is_leaf()) continue;
    first_reference[i] = node.leaf_first();
    if (block_total > std::numeric_limits<std::uint32_t>::max())
      throw Error("kd-tree build: more than 2^32 - 1 leaf blocks; lower max_depth or raise the leaf size");
    node = KdNode::leaf(static_cast<std::uint32_t>(block_total), node.leaf_count());
    block_total += block_count(node.leaf_count());
  }
  layout.blocks.resize(block_total);
  layout.lane_triangle.assign(block_total * kLeafWidth, kInvalidId);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, layout.nodes.size(), 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const KdNode& node = layout.nodes[i];
      if (!node.is_leaf()) continue;
      const std::uint32_t count = node.leaf_count();
      for (std::uint32_t k = 0; k < block_count(count) * kLeafWidth; ++k) {
        LeafBlock& block = layout.blocks[node.leaf_first() + k / kLeafWidth];
        const int lane = static_cast<int>(k % kLeafWidth);
        if (k >= count) {
          block.clear(lane);
          continue;
        }
        const std::uint32_t triangle = tree.references[first_reference[i] + k];
        const std::array<Vec3f, 3>& corners = set.triangles[triangle];
        block.set(lane, corners[0], corners[1], corners[2]);
        layout.lane_triangle[std::size_t{node.leaf_first()} * kLeafWidth + k] = triangle;
      }
    }
  });
  layout.prim = set.prim;
  layout.instance = set.instance;
  layout.bounds = set.bounds;
  AccelStats& s = layout.stats;
  s.node_count = tree.interior_count;
  s.leaf_count = tree.leaf_count;
  s.reference_count = tree.references.size();
  s.max_depth = tree.max_depth;
  s.memory_bytes = layout.memory_bytes();
}

}  // namespace vf::kd
