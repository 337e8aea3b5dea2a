#pragma once
/// \file Depth-first emission of kd nodes during a build, shared by the SAH kd-tree and the median
/// BSP builders, and the parallel recursion that drives both.

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "kdtree/kd_nodes.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/interrupt.hpp"

namespace vf::kd {

/// The growth of one build across all its parallel subtrees, checked against the memory limit as
/// leaves are added: how many triangles a tree references depends on the geometry (straddling
/// triangles are copied into both children), so no estimate made before the build can bound it.
class BuildGrowth {
 public:
  /// `structure` names the build in messages ("kdtree"); the limit is memory_limit() now.
  explicit BuildGrowth(std::string structure);
  /// Counts a leaf of `references` triangles; throws vf::Error once the tree's bytes (about
  /// kBytesPerReference per reference and kBytesPerLeaf per leaf) pass the memory limit. Thread-safe.
  void add_leaf(std::size_t references);

  /// A reference's bytes in the result and the build: its SIMD lane, its index and its share of the
  /// build's node lists (measured: 54 bytes per reference for median-bsp on a 300k soup, leaves included).
  static constexpr double kBytesPerReference = 48.0;
  /// A leaf's node and its partly filled last SIMD block.
  static constexpr double kBytesPerLeaf = 320.0;

 private:
  std::string structure_;
  double limit_bytes_;
  std::string limit_source_;
  std::atomic<std::uint64_t> references_{0};
  std::atomic<std::uint64_t> leaves_{0};
};

/// A (sub)tree in the final layout: nodes depth-first with each left child right after its parent,
/// node and reference indices relative to this tree. Build-only.
struct FlatTree {
  BuildGrowth* growth = nullptr;  ///< Shared by every subtree of one build; may be null.
  std::vector<KdNode> nodes;
  std::vector<std::uint32_t> references;
  std::size_t interior_count = 0;
  std::size_t leaf_count = 0;
  int max_depth = 0;  ///< Levels on the longest root-to-leaf path (a lone root leaf: 1).

  /// An empty tree whose growth is charged to `growth` (may be null).
  explicit FlatTree(BuildGrowth* growth = nullptr) : growth(growth) {}

  /// Appends a leaf at `depth` splits below the root holding `triangles` (ascending indices).
  /// Throws vf::Error when the leaf or the whole tree outgrows the 32-bit node fields.
  void add_leaf(std::span<const std::uint32_t> triangles, int depth);
  /// Appends an interior node whose right child is not yet known; returns its index.
  std::size_t begin_interior();
  /// Completes interior node `index`: split plane, and the right child is the next node appended.
  void end_interior(std::size_t index, int axis, float split);
  /// Appends a whole subtree (its indices shifted to follow what is already here).
  void append(const FlatTree& subtree);
};

/// Moves the built tree into `layout`, copying each leaf's triangles into its SIMD blocks (grouped
/// by position, each block with its box clipped to the leaf cell) and the
/// set's id maps; fills the node, leaf, reference and depth statistics and memory_bytes (not
/// build_ms). Throws vf::Error when the blocks outgrow the 32-bit leaf field.
void finish_layout(FlatTree&& tree, const TriangleSet& set, KdLayout& layout);

/// A node's children as produced by a builder's split(): the plane and the two child inputs.
template <class Node>
struct SplitResult {
  int axis;
  float position;
  Node below, above;
};

/// Nodes with at least this many triangles build their two subtrees as parallel tasks.
inline constexpr std::size_t kParallelSubtreeSize = 2048;

/// Builds the subtree of `node`, `depth` splits below the root, appending it to `out`.
/// `Builder` provides: `std::optional<SplitResult<Node>> split(Node&, int depth) const` (nullopt:
/// make a leaf, the node intact; otherwise the node's storage may have been moved into the children), `std::span<const std::uint32_t>
/// triangles(const Node&) const`, and Node::size(). The result does not depend on the thread count:
/// parallel subtrees are built into their own FlatTree and appended in order.
template <class Builder, class Node>
void build_subtree(const Builder& builder, Node node, int depth, FlatTree& out) {
  const std::size_t size = node.size();
  if (size >= kParallelSubtreeSize) check_interrupt();
  std::optional<SplitResult<Node>> split = builder.split(node, depth);
  if (!split) {
    out.add_leaf(builder.triangles(node), depth);
    return;
  }
  const std::size_t self = out.begin_interior();
  if (size >= kParallelSubtreeSize) {
    FlatTree below(out.growth), above(out.growth);
    vf::parallel_invoke([&] { build_subtree(builder, std::move(split->below), depth + 1, below); },
                         [&] { build_subtree(builder, std::move(split->above), depth + 1, above); });
    out.append(below);
    below = FlatTree();
    out.end_interior(self, split->axis, split->position);
    out.append(above);
  } else {
    build_subtree(builder, std::move(split->below), depth + 1, out);
    out.end_interior(self, split->axis, split->position);
    build_subtree(builder, std::move(split->above), depth + 1, out);
  }
}

/// The build shared by KdTree and MedianBsp (`structure` names it in messages): the subtree of
/// `make_root()` (called only for a non-empty set) built by `builder`, its growth checked against the
/// memory limit, moved into a layout with its statistics and build time.
template <class Builder, class MakeRoot>
std::unique_ptr<const KdLayout> build_layout(const std::string& structure, const TriangleSet& set, const Builder& builder,
                                             MakeRoot&& make_root) {
  const Stopwatch watch;
  auto layout = std::make_unique<KdLayout>();
  BuildGrowth growth(structure);
  FlatTree tree(&growth);
  if (set.size() > 0) build_subtree(builder, make_root(), 0, tree);
  finish_layout(std::move(tree), set, *layout);
  layout->stats.build_ms = watch.elapsed_ms();
  return layout;
}

}  // namespace vf::kd
