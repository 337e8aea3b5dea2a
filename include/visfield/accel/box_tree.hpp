#pragma once
/// \file A BVH over boxes: the top level that tells which of many objects a ray may meet (a field
/// scene's objects), built by the Bvh's SAH builder into its 8-wide nodes and walked by its any-hit
/// traversal, so that the cost per ray grows with the log of the object count.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "visfield/core/bounds.hpp"
#include "visfield/core/ray.hpp"

namespace vf {

/// An immutable 8-wide BVH over boxes, one per item. Queries are const and thread-safe. Move-only.
class BoxTree {
 public:
  /// Builds over `boxes` (item k's box is boxes[k]; an empty box is never met). O(N log N).
  static BoxTree build(std::span<const Bounds3f> boxes);
  BoxTree();
  BoxTree(BoxTree&&) noexcept;
  BoxTree& operator=(BoxTree&&) noexcept;
  ~BoxTree();

  /// Appends to `items` every item whose box `ray` meets within [tmin, tmax], in tree order. Boxes and
  /// range are widened as the Bvh's are, so a ray that touches a box is never left out.
  /// O(log N + items met).
  void items_met(const Ray& ray, std::vector<std::uint32_t>& items) const;
  /// items_met() for many rays: for each i with no skip[i] (every ray when `skip` is null), appends
  /// (item, i) to (`items`, `ray_index`) for every item rays[i] meets. Several rays walk the tree at
  /// once, a step each in turn, so that one's node loads overlap another's; pairs come out grouped by
  /// neither item nor ray. The same pairs as items_met() ray by ray.
  void pairs_met(std::span<const Ray> rays, const std::uint8_t* skip, std::vector<std::uint32_t>& items,
                 std::vector<std::uint32_t>& ray_index) const;
  /// Bytes of its nodes and item list.
  std::size_t memory_bytes() const;

 private:
  struct Layout;
  std::unique_ptr<Layout> layout_;
};

}  // namespace vf
