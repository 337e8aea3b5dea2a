#include "visfield/accel/kdtree.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kdtree/flat_tree.hpp"
#include "kdtree/kd_nodes.hpp"
#include "kdtree/sah_events.hpp"
#include "visfield/core/error.hpp"

namespace vf {
namespace {

void validate(const KdTreeConfig& c, const TriangleSet& set) {
  if (!(c.traversal_cost >= 0.0f) || !std::isfinite(c.traversal_cost))
    throw Error("kdtree: traversal_cost must be finite and >= 0, got " + std::to_string(c.traversal_cost));
  if (!(c.intersection_cost > 0.0f) || !std::isfinite(c.intersection_cost))
    throw Error("kdtree: intersection_cost must be finite and > 0, got " + std::to_string(c.intersection_cost));
  if (!(c.empty_bonus > 0.0f && c.empty_bonus <= 1.0f))
    throw Error("kdtree: empty_bonus must be in (0, 1], got " + std::to_string(c.empty_bonus));
  if (c.max_depth < 0 || c.max_depth > kd::kMaxDepth)
    throw Error("kdtree: max_depth must be in [0, " + std::to_string(kd::kMaxDepth) + "] (0 = automatic), got " +
                std::to_string(c.max_depth));
  // Event keys hold a node-local triangle index in 30 bits.
  if (set.size() >= (std::size_t{1} << 30))
    throw Error("kdtree: " + std::to_string(set.size()) + " triangles exceed the limit of " +
                std::to_string((std::size_t{1} << 30) - 1));
  if (set.size() > 0 && !(is_finite(set.bounds.lo) && is_finite(set.bounds.hi)))
    throw Error("kdtree: the triangle set has non-finite coordinates");
}

/// The depth limit when the config asks for the automatic one: 8 + 1.3 log2(N) splits (pbrt's
/// rule), at most kMaxDepth.
int automatic_max_depth(std::size_t triangle_count) {
  const double n = static_cast<double>(std::max<std::size_t>(triangle_count, 1));
  return std::min(kd::kMaxDepth, static_cast<int>(std::lround(8.0 + 1.3 * std::log2(n))));
}

/// The SAH policy plugged into build_subtree: split while the best plane is cheaper than a leaf,
/// which costs intersection_cost per SIMD block of its triangles.
class SahBuilder {
 public:
  SahBuilder(const TriangleSet& set, const KdTreeConfig& config, int max_depth)
      : set_(set), config_(config), max_depth_(max_depth) {}

  std::optional<kd::SplitResult<kd::SahNode>> split(kd::SahNode& node, int depth) const {
    if (node.size() == 0 || depth >= max_depth_) return std::nullopt;
    const kd::SplitPlane plane = kd::find_best_split(node, config_);
    const double leaf_cost = static_cast<double>(config_.intersection_cost) *
                             static_cast<double>(kd::block_count(static_cast<std::uint32_t>(node.size())));
    if (!(plane.cost < leaf_cost)) return std::nullopt;
    auto [below, above] = kd::split_node(std::move(node), plane, set_);
    return kd::SplitResult<kd::SahNode>{plane.axis, plane.position, std::move(below), std::move(above)};
  }

  std::span<const std::uint32_t> triangles(const kd::SahNode& node) const { return node.triangles; }

 private:
  const TriangleSet& set_;
  KdTreeConfig config_;
  int max_depth_;
};

}  // namespace

KdTree::KdTree(std::unique_ptr<const kd::KdLayout> layout) : layout_(std::move(layout)) {}
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;
KdTree::~KdTree() = default;

KdTree KdTree::build(const TriangleSet& set, const KdTreeConfig& config) {
  validate(config, set);
  const int max_depth = config.max_depth > 0 ? config.max_depth : automatic_max_depth(set.size());
  return KdTree(kd::build_layout(name(), set, SahBuilder(set, config, max_depth), [&] { return kd::make_root(set); }));
}

double KdTree::estimate_build_bytes(std::size_t triangles, const KdTreeConfig&) {
  return 320.0 * static_cast<double>(triangles);
}

Hit KdTree::intersect(const Ray& ray) const { return kd::intersect(*layout_, ray); }
bool KdTree::occluded(const Ray& ray) const { return kd::occluded(*layout_, ray); }
const AccelStats& KdTree::stats() const { return layout_->stats; }

}  // namespace vf
