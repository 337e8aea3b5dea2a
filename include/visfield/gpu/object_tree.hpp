#pragma once
/// \file A binary BVH over a field scene's objects for a GPU, host and device, no STL: what tells a
/// ray which of many field objects it may meet, in O(log objects) instead of one sphere test per
/// object. Each object's box is FieldScene::object_boxes()': its sphere grown by 1% of the radius
/// and 1e-5 of the scene's size, far above the rounding of the sphere cull and of the box test, so
/// the tree never leaves out an object the cull lets in, and the queries answer as testing every
/// sphere does. Built by PackedFieldScene (packed_scene.hpp) where the FieldScene culls by its tree;
/// walked by field_scene_view.hpp.

#include "visfield/core/host_device.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/gpu/bvh_traversal.hpp"

namespace vf::gpu {

/// Most objects one leaf holds.
inline constexpr unsigned int kObjectLeafSize = 4;
/// Entries of a walk's stack: the builder splits at the median, so a tree of N objects is at most
/// log2(N) + 1 levels deep, and it refuses a tree deeper than this.
inline constexpr int kObjectStack = 48;

/// ObjectNode::count of an interior node: this plus the axis its children were split along.
inline constexpr unsigned int kInteriorNode = 0x100;

/// One node, 32 bytes: its box, and either a leaf of `count` (< kInteriorNode) items from
/// items[first], or an interior node (count kInteriorNode + split axis) whose two children are nodes
/// `first` (the lower centroids along the axis) and `first + 1`.
struct alignas(16) ObjectNode {
  float lo[3];
  unsigned int first;
  float hi[3];
  unsigned int count;
};
static_assert(sizeof(ObjectNode) == 32, "ObjectNode is 32 bytes");

/// Whether `n` is a leaf.
VF_HOST_DEVICE inline bool is_leaf(const ObjectNode& n) { return n.count < kInteriorNode; }

/// What a walk reads: borrowed pointers (host or device memory). node_count 0: no tree.
struct ObjectTreeView {
  const ObjectNode* nodes = nullptr;
  const unsigned int* items = nullptr;  ///< Object indices, leaf after leaf.
  unsigned int node_count = 0;
};

/// Whether `ray` meets node `n`'s box within [tmin, tmax] (already widened): the exact BVH's
/// conservative slab test (NaN slabs ignored, far distances scaled up).
VF_HOST_DEVICE inline bool node_met(const ObjectNode& n, const BoxRay& r, float tmin, float tmax) {
  float near_t = tmin, far_t = tmax;
  VF_UNROLL
  for (int a = 0; a < 3; ++a) {
    const float near_plane = r.negative[a] ? n.hi[a] : n.lo[a], far_plane = r.negative[a] ? n.lo[a] : n.hi[a];
    near_t = max_nan_second((near_plane - r.org[a]) * r.inv[a], near_t);
    far_t = min_nan_second((far_plane - r.org[a]) * r.inv[a], far_t);
  }
  return near_t <= scale_far(far_t);
}

/// Calls visit(item) for the items of every leaf whose box `ray` meets within its [tmin, tmax], the
/// nearer child of a split first along the ray (the first objects met are likelier to occlude),
/// until one call returns true; returns whether one did. O(log N + items met).
template <class Visit>
VF_HOST_DEVICE inline bool for_items_met(const ObjectTreeView& tree, const Ray& ray, Visit&& visit) {
  if (tree.node_count == 0) return false;
  const BoxRay box(ray);
  const float tmin = widen_down(ray.tmin), tmax = widen_up(ray.tmax);
  unsigned int stack[kObjectStack];
  int sp = 0;
  unsigned int node = 0;
  for (;;) {
    const ObjectNode& n = tree.nodes[node];
    if (node_met(n, box, tmin, tmax)) {
      if (!is_leaf(n)) {
        const unsigned int far_side = box.negative[n.count - kInteriorNode] ? 0u : 1u;
        stack[sp++] = n.first + far_side;
        node = n.first + (1u - far_side);
        continue;
      }
      for (unsigned int k = n.first; k < n.first + n.count; ++k)
        if (visit(tree.items[k])) return true;
    }
    if (sp == 0) return false;
    node = stack[--sp];
  }
}

}  // namespace vf::gpu
