#include "visfield/accel/bvh_data.hpp"

#include <string>

#include "bvh/binary_builder.hpp"
#include "bvh/collapse.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/stopwatch.hpp"

namespace vf {

WideBvhData build_wide_bvh(const TriangleSet& set, const BvhConfig& config, int leaf_cost_width) {
  if (config.bin_count < 2 || config.bin_count > 64)
    throw Error("bvh data: bin_count must be in [2, 64], got " + std::to_string(config.bin_count));
  if (config.max_leaf_size < 1 || config.max_leaf_size > 16)
    throw Error("bvh data: max_leaf_size must be in [1, 16], got " + std::to_string(config.max_leaf_size));
  if (leaf_cost_width < 1 || leaf_cost_width > 16)
    throw Error("bvh data: leaf_cost_width must be in [1, 16], got " + std::to_string(leaf_cost_width));
  const Stopwatch watch;
  std::vector<Bounds3f> boxes(set.size());
  for (std::size_t i = 0; i < set.size(); ++i)
    for (const Vec3f& p : set.triangles[i]) boxes[i].extend(p);
  const bvh::BinaryTree tree = bvh::build_binary_tree(boxes, config, leaf_cost_width);
  WideBvhData out;
  AlignedVector<bvh::Node8> wide;
  bvh::collapse_to_wide(tree, wide, out.stats, [&](const bvh::BinaryNode& leaf) {
    const auto first = static_cast<std::uint32_t>(out.triangles.size());
    out.triangles.insert(out.triangles.end(), tree.order.begin() + leaf.begin, tree.order.begin() + leaf.begin + leaf.count);
    return bvh::leaf_ref(first, leaf.count);
  });
  out.nodes.resize(wide.size());
  for (std::size_t n = 0; n < wide.size(); ++n)
    for (int slot = 0; slot < 8; ++slot) {
      const bvh::Node8& src = wide[n];
      WideBvhChild& child = out.nodes[n].children[static_cast<std::size_t>(slot)];
      for (int axis = 0; axis < 3; ++axis) {
        child.bounds.lo[axis] = src.bounds[bvh::kLoX + axis][slot];
        child.bounds.hi[axis] = src.bounds[bvh::kHiX + axis][slot];
      }
      if (!(src.bounds[bvh::kLoX][slot] <= src.bounds[bvh::kHiX][slot])) continue;  // unused: an empty box
      const std::uint32_t ref = src.child[slot];
      if (bvh::is_leaf(ref)) {
        child.kind = WideBvhChild::Kind::leaf;
        child.index = bvh::leaf_first_item(ref);
        child.count = bvh::leaf_item_count(ref);
      } else {
        child.kind = WideBvhChild::Kind::node;
        child.index = static_cast<std::uint32_t>(ref / sizeof(bvh::Node8));
      }
    }
  out.stats.reference_count = out.triangles.size();
  out.stats.memory_bytes = out.nodes.size() * sizeof(WideBvhNode) + out.triangles.size() * sizeof(std::uint32_t);
  out.stats.build_ms = watch.elapsed_ms();
  return out;
}

}  // namespace vf
