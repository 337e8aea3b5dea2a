#include "visfield/accel/box_tree.hpp"

#include "bvh/binary_builder.hpp"
#include "bvh/box_test.hpp"
#include "bvh/collapse.hpp"
#include "bvh/wide_traversal.hpp"
#include "visfield/accel/aligned_vector.hpp"

namespace vf {

struct BoxTree::Layout {
  AlignedVector<bvh::Node8> nodes;  // nodes[0] the root whenever there is an item
  std::vector<std::uint32_t> items;  // item indices in leaf order
};

BoxTree::BoxTree() = default;
BoxTree::BoxTree(BoxTree&&) noexcept = default;
BoxTree& BoxTree::operator=(BoxTree&&) noexcept = default;
BoxTree::~BoxTree() = default;

BoxTree BoxTree::build(std::span<const Bounds3f> boxes) {
  BoxTree tree;
  tree.item_count_ = boxes.size();
  tree.layout_ = std::make_unique<Layout>();
  std::vector<std::uint32_t> kept;
  std::vector<Bounds3f> kept_boxes;
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    if (boxes[k].empty()) continue;
    kept.push_back(static_cast<std::uint32_t>(k));
    kept_boxes.push_back(boxes[k]);
  }
  if (kept.empty()) return tree;
  BvhConfig config;
  config.max_leaf_size = 1;  // one item per leaf: a leaf met is an item met
  const bvh::BinaryTree binary = bvh::build_binary_tree(kept_boxes, config, 1);
  AccelStats stats;
  Layout& l = *tree.layout_;
  bvh::collapse_to_wide(binary, l.nodes, stats, [&](const bvh::BinaryNode& leaf) {
    const auto first = static_cast<std::uint32_t>(l.items.size());
    for (std::uint32_t j = 0; j < leaf.count; ++j) l.items.push_back(kept[binary.order[leaf.begin + j]]);
    return bvh::leaf_ref(first, leaf.count);
  });
  return tree;
}

void BoxTree::items_met(const Ray& ray, std::vector<std::uint32_t>& items) const {
  if (!layout_ || layout_->nodes.empty()) return;
  const float inv[3] = {1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z};  // +-inf for +-0
  bvh::BoxRay box;
  box.set(ray, inv);
  const std::uint32_t* order = layout_->items.data();
  bvh::any_hit_walk(layout_->nodes.data(), box, ray.tmin, ray.tmax, [&](std::uint32_t ref) {
    const std::uint32_t first = bvh::leaf_first_item(ref), count = bvh::leaf_item_count(ref);
    items.insert(items.end(), order + first, order + first + count);
    return false;  // every item met, not the first
  });
}

std::size_t BoxTree::memory_bytes() const {
  return layout_ ? layout_->nodes.capacity() * sizeof(bvh::Node8) + layout_->items.capacity() * sizeof(std::uint32_t) : 0;
}

}  // namespace vf
