#include "visfield/accel/median_bsp.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "kdtree/flat_tree.hpp"
#include "kdtree/kd_nodes.hpp"
#include "kdtree/split_rules.hpp"
#include "visfield/core/error.hpp"

namespace vf {
namespace {

void validate(const MedianBspConfig& c, const TriangleSet& set) {
  if (c.max_depth < 0 || c.max_depth > kd::kMaxDepth)
    throw Error("median-bsp: max_depth must be in [0, " + std::to_string(kd::kMaxDepth) + "] (0 = automatic), got " +
                std::to_string(c.max_depth));
  if (c.max_leaf_size < 1)
    throw Error("median-bsp: max_leaf_size must be >= 1, got " + std::to_string(c.max_leaf_size));
  if (set.size() > 0 && !(is_finite(set.bounds.lo) && is_finite(set.bounds.hi)))
    throw Error("median-bsp: the triangle set has non-finite coordinates");
}

/// One node's input: its box, its triangles (TriangleSet indices, ascending) and their bounds in it.
struct MedianNode {
  Bounds3f box;
  std::vector<std::uint32_t> triangles;
  std::vector<Bounds3f> bounds;

  std::size_t size() const { return triangles.size(); }
};

/// The spatial-median policy plugged into build_subtree: halve the longest axis of the box.
class MedianBuilder {
 public:
  MedianBuilder(const TriangleSet& set, const MedianBspConfig& config, int max_depth)
      : set_(set), max_leaf_size_(static_cast<std::size_t>(config.max_leaf_size)), max_depth_(max_depth) {}

  std::optional<kd::SplitResult<MedianNode>> split(MedianNode& node, int depth) const {
    if (node.size() <= max_leaf_size_ || depth >= max_depth_) return std::nullopt;
    const int axis = max_axis(node.box.extent());
    const float p = 0.5f * node.box.lo[axis] + 0.5f * node.box.hi[axis];
    if (!(node.box.lo[axis] < p && p < node.box.hi[axis])) return std::nullopt;  // too thin to halve

    kd::SplitResult<MedianNode> result{axis, p, {}, {}};
    result.below.box = node.box;
    result.below.box.hi[axis] = p;
    result.above.box = node.box;
    result.above.box.lo[axis] = p;
    for (std::size_t t = 0; t < node.size(); ++t) {
      const Bounds3f& b = node.bounds[t];
      const std::uint32_t triangle = node.triangles[t];
      const kd::Side side = kd::side_of(b.lo[axis], b.hi[axis], p, true);
      if (side == kd::Side::both) {
        const std::array<Vec3f, 3>& corners = set_.triangles[triangle];
        add(result.below, triangle, kd::straddler_bounds(corners, b, result.below.box));
        add(result.above, triangle, kd::straddler_bounds(corners, b, result.above.box));
      } else {
        add(side == kd::Side::below ? result.below : result.above, triangle, b);
      }
    }
    // A plane that leaves every triangle on both sides (triangles sharing a vertex or an edge inside
    // the box) separates nothing; splitting on would only copy the node, down to max_depth.
    if (result.below.size() == node.size() && result.above.size() == node.size()) return std::nullopt;
    node = {};
    return result;
  }

  std::span<const std::uint32_t> triangles(const MedianNode& node) const { return node.triangles; }

 private:
  static void add(MedianNode& node, std::uint32_t triangle, const Bounds3f& b) {
    node.triangles.push_back(triangle);
    node.bounds.push_back(b);
  }

  const TriangleSet& set_;
  std::size_t max_leaf_size_;
  int max_depth_;
};

/// One level per doubling of the triangle count: round(log2 N), in [1, kMaxDepth].
int automatic_median_depth(std::size_t triangle_count) {
  const double levels = std::round(std::log2(static_cast<double>(std::max<std::size_t>(triangle_count, 2))));
  return std::clamp(static_cast<int>(levels), 1, kd::kMaxDepth);
}

MedianNode make_root(const TriangleSet& set) {
  MedianNode root;
  root.box = set.bounds;
  root.triangles.resize(set.size());
  root.bounds.resize(set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    root.triangles[i] = static_cast<std::uint32_t>(i);
    for (const Vec3f& p : set.triangles[i]) root.bounds[i].extend(p);
  }
  return root;
}

}  // namespace

MedianBsp::MedianBsp(std::unique_ptr<const kd::KdLayout> layout) : layout_(std::move(layout)) {}
MedianBsp::MedianBsp(MedianBsp&&) noexcept = default;
MedianBsp& MedianBsp::operator=(MedianBsp&&) noexcept = default;
MedianBsp::~MedianBsp() = default;

MedianBsp MedianBsp::build(const TriangleSet& set, const MedianBspConfig& config) {
  validate(config, set);
  const int max_depth = config.max_depth > 0 ? config.max_depth : automatic_median_depth(set.size());
  return MedianBsp(kd::build_layout(name(), set, MedianBuilder(set, config, max_depth), [&] { return make_root(set); }));
}

double MedianBsp::estimate_build_bytes(std::size_t triangles, const MedianBspConfig&) {
  return 256.0 * static_cast<double>(triangles);
}

Hit MedianBsp::intersect(const Ray& ray) const { return kd::intersect(*layout_, ray); }
bool MedianBsp::occluded(const Ray& ray) const { return kd::occluded(*layout_, ray); }
const AccelStats& MedianBsp::stats() const { return layout_->stats; }

}  // namespace vf
