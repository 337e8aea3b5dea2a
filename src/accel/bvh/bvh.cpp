#include "visfield/accel/bvh.hpp"

#include <string>
#include <vector>

#include <tbb/blocked_range.h>

#include "bvh/binary_builder.hpp"
#include "bvh/bvh_layout.hpp"
#include "bvh/collapse.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/parallel.hpp"

namespace vf {
namespace {

void validate(const BvhConfig& c, std::size_t triangle_count) {
  if (c.bin_count < 2 || c.bin_count > 64)
    throw Error("bvh: bin_count must be in [2, 64], got " + std::to_string(c.bin_count));
  const int max_leaf = bvh::kMaxLeafItems * bvh::kLeafWidth;
  if (c.max_leaf_size < 1 || c.max_leaf_size > max_leaf)
    throw Error("bvh: max_leaf_size must be in [1, " + std::to_string(max_leaf) + "], got " +
                std::to_string(c.max_leaf_size));
  if (!(c.traversal_cost >= 0.0f) || !(c.intersection_cost > 0.0f))
    throw Error("bvh: traversal_cost must be >= 0 and intersection_cost > 0");
  // Every triangle may need its own block; block indices have 27 bits.
  if (triangle_count >= (std::size_t{1} << bvh::kLeafCountShift))
    throw Error("bvh: " + std::to_string(triangle_count) + " triangles exceed the limit of " +
                std::to_string((std::size_t{1} << bvh::kLeafCountShift) - 1));
}

std::vector<Bounds3f> triangle_boxes(const TriangleSet& set) {
  std::vector<Bounds3f> boxes(set.size());
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, set.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      for (const Vec3f& p : set.triangles[i]) boxes[i].extend(p);
  });
  return boxes;
}

std::size_t count_blocks(const bvh::BinaryNode& n) {
  if (n.is_leaf()) return (n.count + bvh::kLeafWidth - 1) / bvh::kLeafWidth;
  return count_blocks(*n.left) + count_blocks(*n.right);
}

/// Copies a binary leaf's triangles into SIMD blocks (unused lanes empty) and returns its reference.
std::uint32_t write_triangle_leaf(const bvh::BinaryNode& leaf, const bvh::BinaryTree& tree, const TriangleSet& set,
                                  bvh::BvhLayout& out) {
  using bvh::kLeafWidth;
  const auto first = static_cast<std::uint32_t>(out.blocks.size());
  const std::uint32_t block_count = (leaf.count + kLeafWidth - 1) / kLeafWidth;
  for (std::uint32_t b = 0; b < block_count; ++b) {
    bvh::LeafBlock block;
    for (int lane = 0; lane < kLeafWidth; ++lane) {
      const std::uint32_t j = b * kLeafWidth + static_cast<std::uint32_t>(lane);
      if (j < leaf.count) {
        const std::uint32_t t = tree.order[leaf.begin + j];
        block.triangles.set(lane, set.triangles[t][0], set.triangles[t][1], set.triangles[t][2]);
        block.triangle[lane] = t;
        block.prim[lane] = set.prim[t];
        block.instance[lane] = set.instance[t];
      } else {
        block.triangles.clear(lane);
        block.triangle[lane] = block.prim[lane] = block.instance[lane] = kInvalidId;
      }
    }
    out.blocks.push_back(block);
  }
  out.stats.reference_count += leaf.count;
  return bvh::leaf_ref(first, block_count);
}

}  // namespace

Bvh::Bvh(std::unique_ptr<const bvh::BvhLayout> layout) : layout_(std::move(layout)) {}
Bvh::Bvh(Bvh&&) noexcept = default;
Bvh& Bvh::operator=(Bvh&&) noexcept = default;
Bvh::~Bvh() = default;

Bvh Bvh::build(const TriangleSet& set, const BvhConfig& config) {
  validate(config, set.size());
  const Stopwatch watch;
  auto layout = std::make_unique<bvh::BvhLayout>();
  {
    const bvh::BinaryTree tree = bvh::build_binary_tree(triangle_boxes(set), config, bvh::kLeafWidth);
    if (tree.root) layout->blocks.reserve(count_blocks(*tree.root));
    bvh::collapse_to_wide(tree, layout->nodes, layout->stats, [&](const bvh::BinaryNode& leaf) {
      return write_triangle_leaf(leaf, tree, set, *layout);
    });
  }
  layout->nodes.shrink_to_fit();
  layout->blocks.shrink_to_fit();
  AccelStats& s = layout->stats;
  s.memory_bytes = layout->nodes.capacity() * sizeof(bvh::Node8) + layout->blocks.capacity() * sizeof(bvh::LeafBlock);
  s.build_ms = watch.elapsed_ms();
  return Bvh(std::move(layout));
}

double Bvh::estimate_build_bytes(std::size_t triangles, const BvhConfig&) { return 128.0 * static_cast<double>(triangles); }

Hit Bvh::intersect(const Ray& ray) const { return bvh::intersect(*layout_, ray); }
bool Bvh::occluded(const Ray& ray) const { return bvh::occluded(*layout_, ray); }
Hit Bvh::intersect(const Ray& ray, BvhQueryCounters& counters) const { return bvh::intersect(*layout_, ray, &counters); }
bool Bvh::occluded(const Ray& ray, BvhQueryCounters& counters) const { return bvh::occluded(*layout_, ray, &counters); }
const AccelStats& Bvh::stats() const { return layout_->stats; }

void occluded_block(const Bvh& bvh, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  bvh::occluded_stream(*bvh.layout_, rays, occluded.data());
}

void occluded_batch(const Bvh& bvh, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    check_interrupt();
    occluded_block(bvh, rays.subspan(range.begin(), range.size()), occluded.subspan(range.begin(), range.size()));
  });
}

void intersect_batch(const Bvh& bvh, std::span<const Ray> rays, std::span<Hit> hits) {
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    check_interrupt();
    bvh::intersect_stream(*bvh.layout_, rays.subspan(range.begin(), range.size()), hits.data() + range.begin());
  });
}

}  // namespace vf
