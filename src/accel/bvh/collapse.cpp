#include "bvh/collapse.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "visfield/core/error.hpp"

namespace vf::bvh {
namespace {

// Node boxes are grown by 2^-16 of their largest extent (and at least one ulp). The watertight test
// computes t with an absolute error of a few ulps of the corners' distances along the ray, so a
// triangle hit right at a ray's origin (t ~ 1e-9 where the exact t is 0) or at a tmax equal to its
// computed t may lie just outside its exact box in t; the margin keeps such boxes from being
// culled. Larger boxes contain smaller ones, so the grown boxes nest as well.
constexpr float kBoxMargin = 0x1p-16f;

Bounds3f grown(const Bounds3f& b) {
  const float margin = kBoxMargin * max_component(b.extent());
  Bounds3f out;
  for (int a = 0; a < 3; ++a) {
    out.lo[a] = std::nextafter(b.lo[a] - margin, -std::numeric_limits<float>::infinity());
    out.hi[a] = std::nextafter(b.hi[a] + margin, std::numeric_limits<float>::infinity());
  }
  return out;
}

class Collapser {
 public:
  Collapser(const BinaryTree& tree, const TriangleSet& set, Bvh::Impl& out) : tree_(tree), set_(set), out_(out) {}

  void run() {
    const BinaryNode& root = *tree_.root;
    const std::size_t blocks = count_blocks(root);
    out_.blocks.reserve(blocks);
    out_.lane_triangle.reserve(blocks * kLeafWidth);
    if (root.is_leaf()) {
      // A single leaf still gets a root node, so traversal always starts at nodes[0].
      out_.nodes.push_back(Node8::empty());
      out_.nodes[0].set_bounds(0, grown(root.bounds));
      out_.nodes[0].child[0] = emit_leaf(root, 1);
    } else {
      emit_node(root, 0);
    }
    out_.stats.node_count = out_.nodes.size();
  }

 private:
  static std::size_t count_blocks(const BinaryNode& n) {
    if (n.is_leaf()) return (n.count + kLeafWidth - 1) / kLeafWidth;
    return count_blocks(*n.left) + count_blocks(*n.right);
  }

  // Appends the node for binary node `n` and, depth first, its subtrees; returns its index.
  std::uint32_t emit_node(const BinaryNode& n, int depth) {
    if (out_.nodes.size() >= kMaxNodes)
      throw Error("bvh: the tree needs more than " + std::to_string(kMaxNodes) + " nodes");
    const BinaryNode* kids[8] = {n.left.get(), n.right.get()};
    int count = 2;
    while (count < 8) {
      int open = -1;
      float open_area = -1.0f;
      for (int i = 0; i < count; ++i) {
        if (kids[i]->is_leaf()) continue;
        const float area = kids[i]->bounds.half_area();
        if (area > open_area) {
          open = i;
          open_area = area;
        }
      }
      if (open < 0) break;
      // Keep siblings in tree order: the opened node's children take its place.
      const BinaryNode* opened = kids[open];
      std::copy_backward(kids + open + 1, kids + count, kids + count + 1);
      kids[open] = opened->left.get();
      kids[open + 1] = opened->right.get();
      ++count;
    }
    const auto index = static_cast<std::uint32_t>(out_.nodes.size());
    out_.nodes.push_back(Node8::empty());
    for (int i = 0; i < count; ++i) {
      const std::uint32_t ref =
          kids[i]->is_leaf() ? emit_leaf(*kids[i], depth + 1) : node_ref(emit_node(*kids[i], depth + 1));
      Node8& node = out_.nodes[index];  // re-fetched: emit_node may have grown the array
      node.set_bounds(i, grown(kids[i]->bounds));
      node.child[i] = ref;
    }
    return index;
  }

  std::uint32_t emit_leaf(const BinaryNode& leaf, int depth) {
    const auto first = static_cast<std::uint32_t>(out_.blocks.size());
    const std::uint32_t block_count = (leaf.count + kLeafWidth - 1) / kLeafWidth;
    for (std::uint32_t b = 0; b < block_count; ++b) {
      LeafBlock block;
      for (int lane = 0; lane < kLeafWidth; ++lane) {
        const std::uint32_t j = b * kLeafWidth + static_cast<std::uint32_t>(lane);
        if (j < leaf.count) {
          const std::uint32_t t = tree_.order[leaf.begin + j];
          block.set(lane, set_.triangles[t][0], set_.triangles[t][1], set_.triangles[t][2]);
          out_.lane_triangle.push_back(t);
        } else {
          block.clear(lane);
          out_.lane_triangle.push_back(kInvalidId);
        }
      }
      out_.blocks.push_back(block);
    }
    ++out_.stats.leaf_count;
    out_.stats.reference_count += leaf.count;
    out_.stats.max_depth = std::max(out_.stats.max_depth, depth);
    return leaf_ref(first, block_count);
  }

  const BinaryTree& tree_;
  const TriangleSet& set_;
  Bvh::Impl& out_;
};

}  // namespace

void collapse_to_wide(const BinaryTree& tree, const TriangleSet& set, Bvh::Impl& out) {
  if (!tree.root) return;
  Collapser(tree, set, out).run();
}

}  // namespace vf::bvh
