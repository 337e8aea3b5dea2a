#include "visfield/gpu/gpu_bvh.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>

#include "visfield/accel/bvh_data.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/gpu/bvh_traversal.hpp"

namespace vf::gpu {
namespace {

constexpr std::size_t kMaxTriangles = (std::size_t{1} << 27) - 1;  // leaf references keep 27 bits of triangle index

void validate(const GpuBvhConfig& c, std::size_t triangles) {
  if (c.bin_count < 2 || c.bin_count > 64) throw Error("gpu bvh: bin_count must be in [2, 64], got " + std::to_string(c.bin_count));
  if (c.max_leaf_size < 1 || c.max_leaf_size > kMaxLeafTriangles)
    throw Error("gpu bvh: max_leaf_size must be in [1, " + std::to_string(kMaxLeafTriangles) + "], got " +
                std::to_string(c.max_leaf_size));
  if (triangles > kMaxTriangles)
    throw Error("gpu bvh: " + std::to_string(triangles) + " triangles exceed the limit of " + std::to_string(kMaxTriangles));
}

/// The biased exponent of the smallest power of two s with 255·s >= extent (at least 1).
unsigned int first_exponent(float extent) {
  if (!(extent > 0.0f)) return 1;
  int e2 = 0;
  std::frexp(static_cast<double>(extent) / 255.0, &e2);  // extent/255 < 2^e2
  return static_cast<unsigned int>(std::clamp(e2 + 127, 1, 254));
}

/// Quantises the child boxes of `src` on `axis` into `out`, outward: every decoded lower bound at or
/// below the child's, every upper one at or above, checked with the device's own decode().
void quantise_axis(const WideBvhNode& src, int axis, WideNode& out) {
  const auto box = [&](int slot) -> const Bounds3f& { return src.children[static_cast<std::size_t>(slot)].bounds; };
  float origin = std::numeric_limits<float>::infinity(), top = -std::numeric_limits<float>::infinity();
  for (int slot = 0; slot < 8; ++slot) {
    if (out.meta[slot] == kEmptySlot) continue;
    origin = std::min(origin, box(slot).lo[axis]);
    top = std::max(top, box(slot).hi[axis]);
  }
  out.origin[axis] = origin;
  for (unsigned int e = first_exponent(top - origin); e <= 254; ++e) {
    const float scale = exponent_scale(e);
    bool fits = true;
    for (int slot = 0; slot < 8 && fits; ++slot) {
      if (out.meta[slot] == kEmptySlot) {
        out.lo[axis][slot] = 255;  // never read: empty slots are skipped by their meta byte
        out.hi[axis][slot] = 0;
        continue;
      }
      const float lo = box(slot).lo[axis], hi = box(slot).hi[axis];
      double q = std::floor((static_cast<double>(lo) - origin) / scale);
      unsigned int qlo = static_cast<unsigned int>(std::clamp(q, 0.0, 255.0));
      while (qlo > 0 && decode(origin, qlo, scale) > lo) --qlo;
      q = std::ceil((static_cast<double>(hi) - origin) / scale);
      unsigned int qhi = static_cast<unsigned int>(std::clamp(q, 0.0, 255.0));
      while (qhi < 255 && decode(origin, qhi, scale) < hi) ++qhi;
      fits = decode(origin, qlo, scale) <= lo && decode(origin, qhi, scale) >= hi;
      out.lo[axis][slot] = static_cast<unsigned char>(qlo);
      out.hi[axis][slot] = static_cast<unsigned char>(qhi);
    }
    if (fits) {
      out.exponent[axis] = static_cast<unsigned char>(e);
      return;
    }
  }
  throw Error("gpu bvh: a node's extent on axis " + std::to_string(axis) + " cannot be quantised");
}

}  // namespace

GpuBvh GpuBvh::build(const TriangleSet& set, const GpuBvhConfig& config) {
  validate(config, set.size());
  const Stopwatch watch;
  GpuBvh result;
  BvhConfig binary;
  binary.bin_count = config.bin_count;
  binary.max_leaf_size = config.max_leaf_size;
  // One triangle a leaf cost unit: a GPU thread tests a leaf's triangles one by one.
  const WideBvhData wide = build_wide_bvh(set, binary, 1);

  // Breadth first, so that each node's interior children are consecutive and its leaves' triangles too.
  struct Pending {
    std::size_t source, target;
    int depth;
    unsigned int stacked;  // entries its ancestors can leave on a traversal stack
  };
  std::vector<Pending> queue;
  if (!wide.nodes.empty()) {
    result.nodes_.resize(1);
    queue.push_back({0, 0, 1, 0});
  }
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const Pending p = queue[q];
    const WideBvhNode& src = wide.nodes[p.source];
    WideNode out{};
    std::fill(std::begin(out.meta), std::end(out.meta), kEmptySlot);
    out.child_base = static_cast<unsigned int>(result.nodes_.size());
    out.triangle_base = static_cast<unsigned int>(result.triangles_.size());
    unsigned int slots_used = 0;
    for (const WideBvhChild& c : src.children) slots_used += c.kind != WideBvhChild::Kind::empty ? 1u : 0u;
    // Expanding this node walks one child and pushes at most the others.
    const unsigned int stacked = p.stacked + (slots_used > 0 ? slots_used - 1 : 0);
    result.stack_bound_ = std::max(result.stack_bound_, stacked);
    unsigned int children = 0, leaf_triangles = 0;
    for (int slot = 0; slot < 8; ++slot) {
      const WideBvhChild& c = src.children[static_cast<std::size_t>(slot)];
      if (c.kind == WideBvhChild::Kind::empty) continue;
      if (c.kind == WideBvhChild::Kind::node) {
        out.interior |= static_cast<unsigned char>(1u << slot);
        out.meta[slot] = static_cast<unsigned char>(children++);
        queue.push_back({c.index, out.child_base + children - 1, p.depth + 1, stacked});
        continue;
      }
      out.meta[slot] = static_cast<unsigned char>((c.count - 1) << 5 | leaf_triangles);
      leaf_triangles += c.count;
      for (std::uint32_t k = c.index; k < c.index + c.count; ++k) {
        const std::uint32_t t = wide.triangles[k];
        const auto& corners = set.triangles[t];
        result.triangles_.push_back(WideTriangle{{corners[0].x, corners[0].y, corners[0].z}, t, {corners[1].x, corners[1].y, corners[1].z}, 0u,
                                                 {corners[2].x, corners[2].y, corners[2].z}, 0u});
      }
      ++result.stats_.leaf_count;
      result.stats_.max_depth = std::max(result.stats_.max_depth, p.depth);
    }
    for (int axis = 0; axis < 3; ++axis) quantise_axis(src, axis, out);
    if (result.nodes_.size() + children >= kLeafBit) throw Error("gpu bvh: the tree needs more than 2^31 nodes");
    result.nodes_.resize(result.nodes_.size() + children);
    result.nodes_[p.target] = out;
  }
  result.prim_ = set.prim;
  result.instance_ = set.instance;
  AccelStats& s = result.stats_;
  s.node_count = result.nodes_.size();
  s.reference_count = result.triangles_.size();
  s.memory_bytes = result.nodes_.size() * sizeof(WideNode) + result.triangles_.size() * sizeof(WideTriangle) +
                   (result.prim_.size() + result.instance_.size()) * sizeof(std::uint32_t);
  s.build_ms = watch.elapsed_ms();
  return result;
}

BvhView GpuBvh::view() const {
  return BvhView{nodes_.data(), triangles_.data(), prim_.data(), instance_.data(), static_cast<unsigned int>(nodes_.size()), stack_bound_};
}

Hit GpuBvh::intersect(const Ray& ray) const { return gpu::intersect(view(), ray); }

bool GpuBvh::occluded(const Ray& ray) const { return gpu::occluded(view(), ray); }

}  // namespace vf::gpu
