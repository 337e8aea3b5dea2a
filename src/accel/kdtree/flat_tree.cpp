#include "kdtree/flat_tree.hpp"

#include <algorithm>
#include <span>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>

#include "kdtree/clip.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"

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

BuildGrowth::BuildGrowth(std::string structure) : structure_(std::move(structure)) {
  const MemoryLimit limit = memory_limit();
  limit_bytes_ = limit.bytes;
  limit_source_ = limit.source;
}

void BuildGrowth::add_leaf(std::size_t references) {
  const std::uint64_t refs = references_.fetch_add(references, std::memory_order_relaxed) + references;
  const std::uint64_t leaves = leaves_.fetch_add(1, std::memory_order_relaxed) + 1;
  const double bytes = static_cast<double>(refs) * kBytesPerReference + static_cast<double>(leaves) * kBytesPerLeaf;
  if (bytes > limit_bytes_)
    throw Error(structure_ + ": the tree grew to " + std::to_string(refs) + " triangle references in " + std::to_string(leaves) +
                " leaves, about " + format_bytes(bytes) + ", more than " + limit_source_ +
                " (straddling triangles are copied into both children: a smaller depth or a larger leaf helps)");
}

void FlatTree::add_leaf(std::span<const std::uint32_t> triangles, int depth) {
  if (growth) growth->add_leaf(triangles.size());
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

namespace {

/// Orders `refs` (a leaf's triangles) so that each run of kLeafWidth holds triangles close to one
/// another: recursive halving at the median centroid along the widest axis, the halves cut at a
/// multiple of kLeafWidth.
void group_by_position(std::span<std::uint32_t> refs, const TriangleSet& set) {
  if (refs.size() <= static_cast<std::size_t>(kLeafWidth)) return;
  const auto centroid = [&](std::uint32_t t) {
    const std::array<Vec3f, 3>& c = set.triangles[t];
    return (c[0] + c[1] + c[2]) * (1.0f / 3.0f);
  };
  Bounds3f spread;
  for (const std::uint32_t t : refs) spread.extend(centroid(t));
  const Vec3f extent = spread.hi - spread.lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const std::size_t blocks = block_count(static_cast<std::uint32_t>(refs.size()));
  const std::size_t cut = (blocks / 2) * kLeafWidth;
  std::nth_element(refs.begin(), refs.begin() + static_cast<std::ptrdiff_t>(cut), refs.end(),
                   [&](std::uint32_t a, std::uint32_t b) {
                     const float ca = centroid(a)[axis], cb = centroid(b)[axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  group_by_position(refs.first(cut), set);
  group_by_position(refs.subspan(cut), set);
}

/// Calls f(leaf index, cell box) for every leaf below `index`, whose cell is `box`.
template <class F>
void for_each_leaf_cell(const std::vector<KdNode>& nodes, std::uint32_t index, const Bounds3f& box, F&& f) {
  const KdNode& node = nodes[index];
  if (node.is_leaf()) {
    f(index, box);
    return;
  }
  Bounds3f below = box, above = box;
  below.hi[node.axis()] = node.split();
  above.lo[node.axis()] = node.split();
  for_each_leaf_cell(nodes, index + 1, below, f);
  for_each_leaf_cell(nodes, node.right_child(), above, f);
}

}  // namespace

void finish_layout(FlatTree&& tree, const TriangleSet& set, KdLayout& layout) {
  layout.nodes = std::move(tree.nodes);
  // Leaf i's blocks start at the sum of the block counts of the leaves before it; its references
  // start at first_reference[i]; its cell is cell[i].
  std::vector<std::uint32_t> first_reference(layout.nodes.size(), 0);
  std::vector<Bounds3f> cell(layout.nodes.size());
  if (!layout.nodes.empty())
    for_each_leaf_cell(layout.nodes, 0, set.bounds, [&](std::uint32_t i, const Bounds3f& box) { cell[i] = box; });
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
  for (int axis = 0; axis < 3; ++axis) {
    layout.box_lo[axis].assign(block_total + kBoxWidth, 0.0f);
    layout.box_hi[axis].assign(block_total + kBoxWidth, 0.0f);
  }
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, layout.nodes.size(), 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const KdNode& node = layout.nodes[i];
      if (!node.is_leaf()) continue;
      const std::uint32_t count = node.leaf_count();
      const std::span<std::uint32_t> refs(tree.references.data() + first_reference[i], count);
      group_by_position(refs, set);
      for (std::uint32_t b = 0; b < block_count(count); ++b) {
        const std::uint32_t block_index = node.leaf_first() + b;
        LeafBlock& block = layout.blocks[block_index];
        Bounds3f box;
        for (int lane = 0; lane < kLeafWidth; ++lane) {
          const std::uint32_t k = b * kLeafWidth + static_cast<std::uint32_t>(lane);
          if (k >= count) {
            block.clear(lane);
            continue;
          }
          const std::uint32_t triangle = refs[k];
          const std::array<Vec3f, 3>& corners = set.triangles[triangle];
          block.set(lane, corners[0], corners[1], corners[2]);
          for (const Vec3f& p : corners) box.extend(p);
          layout.lane_triangle[std::size_t{block_index} * kLeafWidth + static_cast<std::uint32_t>(lane)] = triangle;
        }
        // Within the cell: a hit outside it lies in another leaf's cell, tested there.
        box = intersect_bounds(box, cell[i]);
        for (int axis = 0; axis < 3; ++axis) {
          layout.box_lo[axis][block_index] = box.lo[axis];
          layout.box_hi[axis][block_index] = box.hi[axis];
        }
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
