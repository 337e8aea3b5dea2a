#pragma once
/// \file A BVH over boxes: the top level that tells which of many objects a ray may meet (a field
/// scene's objects), built by the Bvh's SAH builder into its 8-wide nodes and walked by its any-hit
/// traversal, so that the cost per ray grows with the log of the object count.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "visfield/core/bounds.hpp"
#include "visfield/core/ray.hpp"

namespace vf {

/// Rays grouped by the item whose box they meet (BoxTree::rays_by_item): list k holds
/// rays[lists[k].begin .. + lists[k].count), the rays of item lists[k].item; the items of one leaf
/// share their rays (lists with the same begin, side by side). Reused between calls.
struct ItemRays {
  /// One item's rays.
  struct List {
    std::uint32_t item, begin, count;
  };
  std::vector<List> lists;
  std::vector<std::uint32_t> rays;
};

/// An immutable 8-wide BVH over boxes, one per item. Queries are const and thread-safe. Move-only.
class BoxTree {
 public:
  /// Builds over `boxes` (item k's box is boxes[k]; an empty box is never met), with at most
  /// `leaf_items` items (in [1, 128]) a leaf; the SAH counts a leaf of up to `leaf_items` as one
  /// test, so leaves fill up where their items lie together. O(N log N).
  static BoxTree build(std::span<const Bounds3f> boxes, int leaf_items = 1);
  BoxTree();
  BoxTree(BoxTree&&) noexcept;
  BoxTree& operator=(BoxTree&&) noexcept;
  ~BoxTree();

  /// Appends to `items` every item whose box `ray` meets within [tmin, tmax], in tree order. Boxes and
  /// range are widened as the Bvh's are, so a ray that touches a box is never left out.
  /// O(log N + items met).
  void items_met(const Ray& ray, std::vector<std::uint32_t>& items) const;
  /// items_met() for many rays, grouped by item: for the rays rays[i] with no skip[i] (every ray
  /// when `skip` is null), `out` gets one list per item some ray's box test lets in, holding those
  /// rays' indices in ascending order; the same (item, ray) pairs as items_met() ray by ray. The
  /// rays go down the tree together, node by node: each node tests its rays and hands each child
  /// those that meet its box, so no ray keeps a walk of its own, and a leaf's rays arrive already
  /// grouped. `width` 16 tests 16 rays at a time against a box (AVX-512 builds), 8 eight (AVX2), 1 a
  /// ray at a time against a node's boxes, 0 the widest this build has: the same lists either way.
  /// O(nodes met by some ray + pairs).
  void rays_by_item(std::span<const Ray> rays, const std::uint8_t* skip, ItemRays& out, int width = 0) const;

  /// A leaf's rays as visit_leaves() hands them on: valid during the call.
  struct LeafRays {
    /// Places past `count` that every column and `ids` can be read at (whole-register loads).
    static constexpr std::size_t kSlack = 16;
    std::span<const std::uint32_t> items;  // the leaf's items
    /// The rays as columns: origin x, y, z, direction x, y, z, tmin, tmax, `count` values each (bit
    /// for bit the rays' own), ids[k] the index of ray k, ascending.
    const float* columns[8];
    const std::uint32_t* ids;
    std::size_t count;
  };
  using LeafVisitor = std::function<void(const LeafRays&)>;
  /// rays_by_item() leaf by leaf, the rays' values with their indices: visit(leaf) for each leaf whose
  /// box some ray with no skip[i] meets, with the same (item, ray) pairs, except that a ray the visits
  /// settle (skip[i] set by the visitor) may be left out of the leaves visited after. On lanes (8 or
  /// 16) the values go down the tree with the rays, each node's children nearest its rays' mean origin first,
  /// settled rays stop where the walk next reads their skip, and a leaf is visited as soon as it is
  /// reached, while its rays are in cache; a ray at a time, leaves come in tree order.
  /// O(nodes met by some ray + pairs).
  void visit_leaves(std::span<const Ray> rays, const std::uint8_t* skip, const LeafVisitor& visit, int width = 0) const;
  /// The rays a rays_by_item() step tests together for `width` (0: the widest) in this build: 16, 8 or 1.
  static int batch_width(int width = 0);
  /// Bytes of its nodes and item list.
  std::size_t memory_bytes() const;

 private:
  struct Layout;
  std::unique_ptr<Layout> layout_;
};

}  // namespace vf
