#include "visfield/accel/bvh.hpp"

#include <chrono>
#include <string>

#include "bvh/binary_builder.hpp"
#include "bvh/bvh_impl.hpp"
#include "bvh/collapse.hpp"
#include "visfield/core/error.hpp"

namespace vf {
namespace {

void validate(const BvhConfig& c, std::size_t triangle_count) {
  if (c.bin_count < 2 || c.bin_count > 64)
    throw Error("bvh: bin_count must be in [2, 64], got " + std::to_string(c.bin_count));
  const int max_leaf = bvh::kMaxLeafBlocks * bvh::kLeafWidth;
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

}  // namespace

Bvh::Bvh(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Bvh::Bvh(Bvh&&) noexcept = default;
Bvh& Bvh::operator=(Bvh&&) noexcept = default;
Bvh::~Bvh() = default;

Bvh Bvh::build(const TriangleSet& set, const BvhConfig& config) {
  validate(config, set.size());
  const auto start = std::chrono::steady_clock::now();
  auto impl = std::make_unique<Impl>();
  impl->config = config;
  {
    const bvh::BinaryTree tree = bvh::build_binary_tree(set, config, bvh::kLeafWidth);
    bvh::collapse_to_wide(tree, set, *impl);
  }
  impl->nodes.shrink_to_fit();
  impl->blocks.shrink_to_fit();
  impl->lane_triangle.shrink_to_fit();
  impl->prim = set.prim;
  impl->instance = set.instance;
  AccelStats& s = impl->stats;
  s.memory_bytes = impl->nodes.capacity() * sizeof(bvh::Node8) + impl->blocks.capacity() * sizeof(bvh::LeafBlock) +
                   (impl->lane_triangle.capacity() + impl->prim.capacity() + impl->instance.capacity()) *
                       sizeof(std::uint32_t);
  s.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return Bvh(std::move(impl));
}

std::optional<Hit> Bvh::intersect(const Ray& ray) const { return impl_->intersect(ray); }
bool Bvh::occluded(const Ray& ray) const { return impl_->occluded(ray); }
const AccelStats& Bvh::stats() const { return impl_->stats; }

}  // namespace vf
