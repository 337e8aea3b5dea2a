#pragma once
/// \file The 8-wide node format (private to the accel module), shared by the triangle Bvh and the
/// instance layer's top level: child boxes in structure-of-arrays form, child references that name
/// either a node or a leaf (a run of leaf items whose meaning belongs to the tree's owner).

#include <cstdint>
#include <limits>
#include <vector>

#include "visfield/core/bounds.hpp"

namespace vf::bvh {

/// A leaf holds at most this many items (4 bits of the child reference): triangle blocks in the
/// Bvh, objects in the instance layer's top level.
inline constexpr int kMaxLeafItems = 16;
/// No leaf is deeper than this many binary levels, so traversal stacks have a fixed size.
inline constexpr int kMaxBinaryDepth = 64;

/// Child references: an interior child is the byte offset of its Node8 in the node array (an
/// offset rather than an index saves a multiplication on the traversal's critical path); a leaf
/// child has kLeafFlag set, its item count minus one in bits 27..30 and its first item index in
/// bits 0..26.
inline constexpr std::uint32_t kLeafFlag = 1u << 31;
inline constexpr int kLeafCountShift = 27;
inline constexpr std::uint32_t kLeafFirstMask = (1u << kLeafCountShift) - 1;

/// Builds the reference of a leaf of `count` (1..kMaxLeafItems) items starting at item `first`.
constexpr std::uint32_t leaf_ref(std::uint32_t first, std::uint32_t count) {
  return kLeafFlag | ((count - 1) << kLeafCountShift) | first;
}
constexpr bool is_leaf(std::uint32_t ref) { return (ref & kLeafFlag) != 0; }
constexpr std::uint32_t leaf_first_item(std::uint32_t ref) { return ref & kLeafFirstMask; }
constexpr std::uint32_t leaf_item_count(std::uint32_t ref) { return ((ref >> kLeafCountShift) & 15u) + 1; }

/// Bounds rows of a Node8.
enum BoundsRow { kLoX, kLoY, kLoZ, kHiX, kHiY, kHiZ };

/// An interior node with up to eight children. Unused slots have empty boxes (lo = +inf,
/// hi = -inf), which no ray enters.
struct alignas(64) Node8 {
  float bounds[6][8];
  std::uint32_t child[8];

  /// A node whose eight slots are all unused.
  static Node8 empty() {
    Node8 n{};
    for (int slot = 0; slot < 8; ++slot) {
      for (int axis = 0; axis < 3; ++axis) {
        n.bounds[kLoX + axis][slot] = std::numeric_limits<float>::infinity();
        n.bounds[kHiX + axis][slot] = -std::numeric_limits<float>::infinity();
      }
      n.child[slot] = 0;
    }
    return n;
  }
  /// Sets the box of `slot`.
  void set_bounds(int slot, const Bounds3f& b) {
    for (int axis = 0; axis < 3; ++axis) {
      bounds[kLoX + axis][slot] = b.lo[axis];
      bounds[kHiX + axis][slot] = b.hi[axis];
    }
  }
};

/// Reference of the interior node nodes[index].
constexpr std::uint32_t node_ref(std::size_t index) { return static_cast<std::uint32_t>(index * sizeof(Node8)); }
/// The node an interior reference names.
inline const Node8& node_at(const Node8* nodes, std::uint32_t ref) {
  return *reinterpret_cast<const Node8*>(reinterpret_cast<const char*>(nodes) + ref);
}
/// Interior references are byte offsets below kLeafFlag: the node array may not exceed this.
inline constexpr std::size_t kMaxNodes = kLeafFlag / sizeof(Node8);

}  // namespace vf::bvh
