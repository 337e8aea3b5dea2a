#pragma once
/// \file The exact BVH in its GPU layout (bvh_layout.hpp), made on the host from the CPU Bvh's tree
/// as plain data (accel/bvh_data.hpp: the binned SAH tree collapsed to 8-wide nodes whose boxes are
/// grown for the watertight test), laid out breadth first with each node's children and triangles
/// consecutive and its child boxes quantised outward. The host
/// queries run the device traversal's code (bvh_traversal.hpp) on the host copy.

#include <cstdint>
#include <vector>

#include "visfield/accel/query.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/gpu/bvh_layout.hpp"

namespace vf::gpu {

/// Build parameters: the CPU Bvh's SAH settings with leaves of at most kMaxLeafTriangles triangles
/// (one triangle a leaf item, so that a GPU thread tests no padding).
struct GpuBvhConfig {
  int bin_count = 32;      ///< SAH bins per axis, in [2, 64].
  int max_leaf_size = 4;   ///< Triangles per leaf, in [1, kMaxLeafTriangles].
};

/// An immutable BVH in the GPU layout, in host memory. Queries are const and thread-safe. Movable.
class GpuBvh {
 public:
  /// Builds over `set` (copied in leaf order). O(N log N), parallel (TBB). Throws vf::Error on a bad
  /// config or more than 2^27 − 1 triangles.
  static GpuBvh build(const TriangleSet& set, const GpuBvhConfig& config = {});

  /// The host arrays as a traversal reads them (valid while this lives).
  BvhView view() const;
  /// Nodes, breadth first; nodes()[0] is the root when there are triangles.
  const std::vector<WideNode>& nodes() const { return nodes_; }
  /// Triangles in leaf order.
  const std::vector<WideTriangle>& triangles() const { return triangles_; }
  /// Triangle id in its mesh, by TriangleSet index.
  const std::vector<std::uint32_t>& prim() const { return prim_; }
  /// Object id, by TriangleSet index.
  const std::vector<std::uint32_t>& instance() const { return instance_; }

  /// Closest hit in (tmin, tmax] by the device traversal's code: BruteForce's answer.
  Hit intersect(const Ray& ray) const;
  /// Any hit in (tmin, tmax] by the device traversal's code.
  bool occluded(const Ray& ray) const;
  /// Nodes, leaves, triangle references, depth (8-wide levels), bytes of the four arrays, build ms.
  const AccelStats& stats() const { return stats_; }
  /// Most entries a traversal stack holds in this tree (BvhView::stack_bound).
  unsigned int stack_bound() const { return stack_bound_; }

 private:
  std::vector<WideNode> nodes_;
  std::vector<WideTriangle> triangles_;
  std::vector<std::uint32_t> prim_, instance_;
  AccelStats stats_;
  unsigned int stack_bound_ = 0;
};

}  // namespace vf::gpu
