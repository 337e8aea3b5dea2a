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
  Collapser(AlignedVector<Node8>& nodes, AccelStats& stats, const LeafWriter& write_leaf)
      : nodes_(nodes), stats_(stats), write_leaf_(write_leaf) {}

  void run(const BinaryNode& root) {
    if (root.is_leaf()) {
      // A single leaf still gets a root node, so traversal always starts at nodes[0].
      nodes_.push_back(Node8::empty());
      nodes_[0].set_bounds(0, grown(root.bounds));
      nodes_[0].child[0] = emit_leaf(root, 1);
    } else {
      emit_node(root, 0);
    }
    stats_.node_count = nodes_.size();
  }

 private:
  // Appends the node for binary node `n` and, depth first, its subtrees; returns its index.
  std::uint32_t emit_node(const BinaryNode& n, int depth) {
    if (nodes_.size() >= kMaxNodes) throw Error("bvh: the tree needs more than " + std::to_string(kMaxNodes) + " nodes");
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
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back(Node8::empty());
    for (int i = 0; i < count; ++i) {
      const std::uint32_t ref =
          kids[i]->is_leaf() ? emit_leaf(*kids[i], depth + 1) : node_ref(emit_node(*kids[i], depth + 1));
      Node8& node = nodes_[index];  // re-fetched: emit_node may have grown the array
      node.set_bounds(i, grown(kids[i]->bounds));
      node.child[i] = ref;
    }
    return index;
  }

  std::uint32_t emit_leaf(const BinaryNode& leaf, int depth) {
    ++stats_.leaf_count;
    stats_.max_depth = std::max(stats_.max_depth, depth);
    return write_leaf_(leaf);
  }

  AlignedVector<Node8>& nodes_;
  AccelStats& stats_;
  const LeafWriter& write_leaf_;
};

}  // namespace

void collapse_to_wide(const BinaryTree& tree, AlignedVector<Node8>& nodes, AccelStats& stats,
                      const LeafWriter& write_leaf) {
  if (!tree.root) return;
  Collapser(nodes, stats, write_leaf).run(*tree.root);
}

}  // namespace vf::bvh
