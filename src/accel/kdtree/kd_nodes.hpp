#pragma once
/// \file The node layout and traversal shared by KdTree and MedianBsp (private to the accel
/// module): compact 8-byte nodes in depth-first order, leaves pointing into an array of SIMD
/// triangle blocks, and the front-to-back stack traversal over them.

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "simd/watertight_block.hpp"
#include "visfield/accel/query.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/core/bounds.hpp"
#include "visfield/core/ray.hpp"

namespace vf::kd {

/// No leaf lies below more than this many splits; the traversal stack has this many entries.
inline constexpr int kMaxDepth = 64;
/// Largest right-child index or leaf reference count a node can hold (30 bits).
inline constexpr std::uint32_t kMaxNodePayload = (1u << 30) - 1;

/// One node in 8 bytes (pbrt / Wald layout). Interior: the split position and, in `packed`, the
/// split axis (bits 0..1) and the index of the right child (bits 2..31); the left child is the next
/// node. Leaf: leaf_first(), the index of its first triangle reference (in a FlatTree during the
/// build) or of its first block (in a KdLayout), and, in `packed`, the tag 3 (bits 0..1) and
/// leaf_count(), its number of triangles (bits 2..31).
struct KdNode {
  std::uint32_t word = 0;
  std::uint32_t packed = 3;

  /// An interior node splitting `axis` (0..2) at `split`; `right` <= kMaxNodePayload.
  static KdNode interior(int axis, float split, std::uint32_t right) {
    return {std::bit_cast<std::uint32_t>(split), (right << 2) | static_cast<std::uint32_t>(axis)};
  }
  /// A leaf of `count` (<= kMaxNodePayload) triangles starting at reference or block `first`.
  static KdNode leaf(std::uint32_t first, std::uint32_t count) { return {first, (count << 2) | 3u}; }

  bool is_leaf() const { return (packed & 3u) == 3u; }
  int axis() const { return static_cast<int>(packed & 3u); }
  float split() const { return std::bit_cast<float>(word); }
  std::uint32_t right_child() const { return packed >> 2; }
  std::uint32_t leaf_first() const { return word; }
  std::uint32_t leaf_count() const { return packed >> 2; }
};
static_assert(sizeof(KdNode) == 8);

/// Triangles per leaf block: leaves hold their triangles in SIMD blocks of this width, tested with
/// the oracle's block kernel (bit-identical to intersect_triangle). With AVX-512 a block of 16
/// costs about what one of 8 does, and the SAH counts blocks, so wide blocks mean fewer nodes.
inline constexpr int kLeafWidth = 16;
using LeafBlock = simd::TriangleBlock<kLeafWidth>;

/// Number of blocks of a leaf holding `count` triangles.
constexpr std::uint32_t block_count(std::uint32_t count) { return (count + kLeafWidth - 1) / kLeafWidth; }

/// Blocks whose boxes one leaf step tests at once.
inline constexpr int kBoxWidth = 8;

/// A built kd-tree or BSP: immutable, queried concurrently. nodes[0] is the root whenever the
/// triangle set is non-empty. A leaf's triangles fill the lanes of block_count(leaf_count())
/// consecutive blocks from block leaf_first(), grouped by position so that each block's box is
/// small (unused lanes empty). A triangle crossing several leaves is stored in each.
struct KdLayout {
  std::vector<KdNode> nodes;
  AlignedVector<LeafBlock> blocks;
  std::vector<std::uint32_t> lane_triangle;  ///< TriangleSet index per block lane; kInvalidId in unused lanes.
  /// Per block, per axis: the bounds of its triangles within its leaf's cell (box_lo[axis][block]),
  /// followed by kBoxWidth padding entries so that any block starts a full load.
  std::array<std::vector<float>, 3> box_lo, box_hi;
  std::vector<std::uint32_t> prim;           ///< Copy of the TriangleSet's triangle ids.
  std::vector<ObjectId> instance;            ///< Copy of the TriangleSet's object ids.
  Bounds3f bounds;                           ///< The root cell: bounds of all triangles.
  AccelStats stats;

  /// Bytes held by the arrays (capacity).
  std::size_t memory_bytes() const;
};

/// Closest hit in (tmin, tmax]: bit-identical (t, u, v, triangle) to intersect_triangle() run on
/// every triangle in TriangleSet order with ties going to the lowest index. Thread-safe.
Hit intersect(const KdLayout& kd, const Ray& ray);

/// True when some triangle is hit in (tmin, tmax]; stops at the first hit found. Thread-safe.
bool occluded(const KdLayout& kd, const Ray& ray);

}  // namespace vf::kd
