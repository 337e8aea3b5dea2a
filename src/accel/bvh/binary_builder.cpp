#include "bvh/binary_builder.hpp"

#include <algorithm>
#include <cmath>
#include <array>
#include <bit>
#include <limits>
#include <new>
#include <utility>

#include <tbb/blocked_range.h>

#include "bvh/wide_nodes.hpp"
#include "simd/lanes.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/interrupt.hpp"

namespace vf::bvh {
namespace {

using V4 = simd::Lanes<4>;

constexpr int kMaxBins = 64;
// Ranges at least this large are binned in parallel and their halves built as separate tasks.
constexpr std::uint32_t kParallelBinning = 1u << 14;
constexpr std::uint32_t kParallelSubtree = 1u << 12;

/// A box as two 4-lane vectors (x, y, z, unused), so that growing it is two SIMD operations.
struct Box4 {
  V4 lo = V4::broadcast(std::numeric_limits<float>::infinity());
  V4 hi = V4::broadcast(-std::numeric_limits<float>::infinity());

  void extend(const Box4& b) {
    lo = min_nan_second(b.lo, lo);
    hi = max_nan_second(b.hi, hi);
  }
  void extend(const V4& p) {
    lo = min_nan_second(p, lo);
    hi = max_nan_second(p, hi);
  }
  /// Half the surface area; the box must not be empty.
  float half_area() const {
    alignas(16) float e[4];
    (hi - lo).store(e);
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  }
  Vec3f lower() const { return component(lo); }
  Vec3f upper() const { return component(hi); }
  Bounds3f bounds() const { return {lower(), upper()}; }

 private:
  static Vec3f component(const V4& v) {
    alignas(16) float f[4];
    v.store(f);
    return {f[0], f[1], f[2]};
  }
};

/// Twice the centroid of a box (the factor does not matter for binning).
inline V4 centroid2(const Box4& b) { return b.lo + b.hi; }

struct Bin {
  Box4 box;
  std::uint32_t count = 0;
};

/// Bins of the three axes for one range. Only the first `bin_count` bins of each axis are
/// initialised and used: most ranges are small, and clearing all kMaxBins would dominate their cost.
class Binning {
 public:
  explicit Binning(int bin_count) : bin_count_(bin_count) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < bin_count; ++b) new (&storage_.bins[a][b]) Bin();
  }
  Binning(const Binning&) = delete;
  Binning& operator=(const Binning&) = delete;

  Bin* axis(int a) { return storage_.bins[a]; }
  const Bin* axis(int a) const { return storage_.bins[a]; }

  void merge(const Binning& o) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < bin_count_; ++b) {
        storage_.bins[a][b].box.extend(o.storage_.bins[a][b].box);
        storage_.bins[a][b].count += o.storage_.bins[a][b].count;
      }
  }

 private:
  union Storage {
    Storage() {}
    Bin bins[3][kMaxBins];
  } storage_;
  int bin_count_;
};

/// Maps a (doubled) centroid to its bin on each axis.
struct BinMapping {
  V4 lo;
  V4 scale;  // bins / extent, 0 on axes without extent
  int bin_count;

  std::array<int, 3> bins(const V4& c2) const {
    alignas(16) float f[4];
    ((c2 - lo) * scale).store(f);
    return {std::min(static_cast<int>(f[0]), bin_count - 1), std::min(static_cast<int>(f[1]), bin_count - 1),
            std::min(static_cast<int>(f[2]), bin_count - 1)};
  }
  int bin(const V4& c2, int axis) const { return bins(c2)[axis]; }
};

/// A range of `order` with the bounds of its boxes and of their (doubled) centroids.
struct Range {
  std::uint32_t begin, end;
  Box4 bounds, centroids;
  std::uint32_t size() const { return end - begin; }
};

class Builder {
 public:
  Builder(std::span<const Bounds3f> boxes, const BvhConfig& config, int leaf_width)
      : config_(config), leaf_width_(leaf_width), prims_(boxes.size()) {
    vf::parallel_for(tbb::blocked_range<std::size_t>(0, boxes.size(), 4096), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        alignas(16) const float lo[4] = {boxes[i].lo.x, boxes[i].lo.y, boxes[i].lo.z, 0.0f};
        alignas(16) const float hi[4] = {boxes[i].hi.x, boxes[i].hi.y, boxes[i].hi.z, 0.0f};
        Box4 b;
        b.extend(V4::load(lo));
        b.extend(V4::load(hi));
        prims_[i] = b;
      }
    });
  }

  BinaryTree build() {
    BinaryTree tree;
    const auto n = static_cast<std::uint32_t>(prims_.size());
    tree.order.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) tree.order[i] = i;
    if (n == 0) return tree;
    order_ = tree.order.data();
    Range root{0, n, {}, {}};
    for (std::uint32_t i = 0; i < n; ++i) {
      root.bounds.extend(prims_[i]);
      root.centroids.extend(centroid2(prims_[i]));
    }
    tree.root = build_node(root, 0);
    return tree;
  }

 private:
  struct Split {
    int axis = -1;
    int bin = 0;
    float cost = 0.0f;
    Box4 left, right;
  };

  float blocks(std::uint32_t n) const { return static_cast<float>((n + leaf_width_ - 1) / leaf_width_); }

  float leaf_cost(const Range& r) const {
    return config_.intersection_cost * blocks(r.size()) * r.bounds.half_area();
  }

  // Number of median splits that bring n triangles down to leaf size.
  int median_levels(std::uint32_t n) const {
    const std::uint32_t leaves = (n + config_.max_leaf_size - 1) / config_.max_leaf_size;
    return leaves <= 1 ? 0 : static_cast<int>(std::bit_width(leaves - 1));
  }

  void bin_into(Binning& binning, const BinMapping& map, std::uint32_t begin, std::uint32_t end) const {
    for (std::uint32_t i = begin; i < end; ++i) {
      const Box4& box = prims_[order_[i]];
      const std::array<int, 3> b = map.bins(centroid2(box));
      for (int a = 0; a < 3; ++a) {
        Bin& bin = binning.axis(a)[b[a]];
        bin.box.extend(box);
        ++bin.count;
      }
    }
  }

  void bin_range(const Range& r, const BinMapping& map, Binning& out) const {
    if (r.size() < kParallelBinning) {
      bin_into(out, map, r.begin, r.end);
      return;
    }
    // Boxes merge by min/max and counts by addition, so the result is the same however TBB splits.
    struct Body {
      const Builder& builder;
      const BinMapping& map;
      Binning own;
      Binning* binning;  // the caller's for the root body, `own` for split bodies
      Body(const Builder& b, const BinMapping& m, Binning& target)
          : builder(b), map(m), own(1), binning(&target) {}
      Body(Body& o, tbb::split) : builder(o.builder), map(o.map), own(o.map.bin_count), binning(&own) {}
      void operator()(const tbb::blocked_range<std::uint32_t>& br) {
        builder.bin_into(*binning, map, br.begin(), br.end());
      }
      void join(const Body& o) { binning->merge(*o.binning); }
    };
    Body body(*this, map, out);
    vf::parallel_reduce(tbb::blocked_range<std::uint32_t>(r.begin, r.end, 4096), body);
  }

  Split find_split(const Range& r, BinMapping& map) const {
    // Few bins for small ranges (as Embree does): their splits hardly improve with more, and the
    // bins' set-up and sweeps would dominate the cost of binning a few triangles.
    const int bins = static_cast<int>(std::min(static_cast<std::uint32_t>(config_.bin_count), 4 + r.size() / 20));
    alignas(16) float lo[4], hi[4];
    r.centroids.lo.store(lo);
    r.centroids.hi.store(hi);
    alignas(16) float scale[4] = {0, 0, 0, 0};
    bool any_axis = false;
    for (int a = 0; a < 3; ++a) {
      // An extent so small (a denormal) that bins / extent overflows is no extent to bin along:
      // 0 * inf would give the centroid at `lo` a NaN bin.
      const float extent = hi[a] - lo[a];
      const float per_unit = static_cast<float>(bins) / extent;
      const bool binned = extent > 0.0f && std::isfinite(per_unit);
      scale[a] = binned ? per_unit : 0.0f;
      any_axis = any_axis || binned;
    }
    map = BinMapping{r.centroids.lo, V4::load(scale), bins};
    Split best;
    if (!any_axis) return best;
    Binning binning(bins);
    bin_range(r, map, binning);
    std::array<float, kMaxBins> right_area{};
    std::array<std::uint32_t, kMaxBins> right_count{};
    for (int a = 0; a < 3; ++a) {
      if (!(scale[a] > 0.0f)) continue;
      const Bin* axis_bins = binning.axis(a);
      Box4 acc;
      std::uint32_t count = 0;
      for (int b = bins - 1; b > 0; --b) {
        acc.extend(axis_bins[b].box);
        count += axis_bins[b].count;
        right_area[b] = count > 0 ? acc.half_area() : 0.0f;
        right_count[b] = count;
      }
      acc = Box4{};
      count = 0;
      for (int b = 1; b < bins; ++b) {
        acc.extend(axis_bins[b - 1].box);
        count += axis_bins[b - 1].count;
        if (count == 0 || right_count[b] == 0) continue;
        const float cost = config_.intersection_cost *
                           (acc.half_area() * blocks(count) + right_area[b] * blocks(right_count[b]));
        if (best.axis < 0 || cost < best.cost) {
          best.axis = a;
          best.bin = b;
          best.cost = cost;
        }
      }
    }
    if (best.axis < 0) return best;
    best.cost += config_.traversal_cost * r.bounds.half_area();
    for (int b = 0; b < bins; ++b) (b < best.bin ? best.left : best.right).extend(binning.axis(best.axis)[b].box);
    return best;
  }

  // Partitions r by the split's bin, gathering each side's centroid bounds on the way; the box
  // bounds come from the bins.
  std::pair<Range, Range> partition(const Range& r, const BinMapping& map, const Split& split) const {
    const auto goes_left = [&](std::uint32_t t) { return map.bin(centroid2(prims_[t]), split.axis) < split.bin; };
    std::uint32_t* lo = order_ + r.begin;
    std::uint32_t* hi = order_ + r.end;
    Box4 left_centroids, right_centroids;
    for (;;) {
      while (lo < hi && goes_left(*lo)) left_centroids.extend(centroid2(prims_[*lo++]));
      while (lo < hi && !goes_left(hi[-1])) right_centroids.extend(centroid2(prims_[*--hi]));
      if (lo == hi) break;
      std::swap(*lo, hi[-1]);
    }
    const auto mid = static_cast<std::uint32_t>(lo - order_);
    return {Range{r.begin, mid, split.left, left_centroids}, Range{mid, r.end, split.right, right_centroids}};
  }

  // Splits at the median of the centroids along their widest axis (ties by triangle index, so the
  // result is fully determined by the input).
  std::pair<Range, Range> median_split(const Range& r) const {
    const Vec3f extent = r.centroids.upper() - r.centroids.lower();
    const int axis = max_axis(extent);
    const std::uint32_t mid = r.begin + r.size() / 2;
    const auto key = [&](std::uint32_t t) {
      alignas(16) float c[4];
      centroid2(prims_[t]).store(c);
      return c[axis];
    };
    std::nth_element(order_ + r.begin, order_ + mid, order_ + r.end, [&](std::uint32_t x, std::uint32_t y) {
      const float cx = key(x), cy = key(y);
      return cx < cy || (cx == cy && x < y);
    });
    Range left{r.begin, mid, {}, {}}, right{mid, r.end, {}, {}};
    for (Range* c : {&left, &right})
      for (std::uint32_t i = c->begin; i < c->end; ++i) {
        c->bounds.extend(prims_[order_[i]]);
        c->centroids.extend(centroid2(prims_[order_[i]]));
      }
    return {left, right};
  }

  std::unique_ptr<BinaryNode> make_leaf(const Range& r) const {
    auto node = std::make_unique<BinaryNode>();
    node->bounds = r.bounds.bounds();
    node->begin = r.begin;
    node->count = r.size();
    return node;
  }

  std::unique_ptr<BinaryNode> build_node(const Range& r, int depth) {
    const std::uint32_t n = r.size();
    if (n >= kParallelBinning) check_interrupt();
    const bool fits_leaf = n <= static_cast<std::uint32_t>(config_.max_leaf_size);
    if (n == 1) return make_leaf(r);
    std::pair<Range, Range> halves;
    if (depth + median_levels(n) >= kMaxBinaryDepth) {
      // Depth budget spent: halve by count so that the deepest leaf stays within kMaxBinaryDepth.
      if (fits_leaf) return make_leaf(r);
      halves = median_split(r);
    } else {
      BinMapping map{};
      const Split split = find_split(r, map);
      if (split.axis < 0) {
        if (fits_leaf) return make_leaf(r);
        halves = median_split(r);
      } else {
        if (fits_leaf && leaf_cost(r) <= split.cost) return make_leaf(r);
        halves = partition(r, map, split);
      }
    }
    auto node = std::make_unique<BinaryNode>();
    node->bounds = r.bounds.bounds();
    if (n >= kParallelSubtree) {
      vf::parallel_invoke([&] { node->left = build_node(halves.first, depth + 1); },
                           [&] { node->right = build_node(halves.second, depth + 1); });
    } else {
      node->left = build_node(halves.first, depth + 1);
      node->right = build_node(halves.second, depth + 1);
    }
    return node;
  }

  const BvhConfig& config_;
  const int leaf_width_;
  AlignedVector<Box4> prims_;
  std::uint32_t* order_ = nullptr;
};

}  // namespace

BinaryTree build_binary_tree(std::span<const Bounds3f> boxes, const BvhConfig& config, int leaf_width) {
  return Builder(boxes, config, leaf_width).build();
}

}  // namespace vf::bvh
