#pragma once
/// \file Memory layout of the built Bvh (private to the accel module): 8-wide nodes whose leaves are
/// runs of SIMD triangle blocks.

#include <cstdint>
#include <span>
#include <vector>

#include "bvh/wide_nodes.hpp"
#include "simd/watertight_block.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/query.hpp"

namespace vf::bvh {

/// Triangles per leaf block (the SIMD width of the leaf triangle test).
inline constexpr int kLeafWidth = 8;

/// A leaf block: kLeafWidth triangles for the SIMD test, then per lane what a closest hit reports,
/// on the lines right after them (a hit reads them from lines the test has just brought in, not
/// from arrays in TriangleSet order elsewhere). 384 bytes, six cache lines.
struct alignas(64) LeafBlock {
  simd::TriangleBlock<kLeafWidth> triangles;  ///< NaN corners in unused lanes.
  std::uint32_t triangle[kLeafWidth];         ///< TriangleSet index per lane (ties: the lowest wins); kInvalidId in unused lanes.
  std::uint32_t prim[kLeafWidth];             ///< The TriangleSet's triangle id per lane.
  ObjectId instance[kLeafWidth];              ///< The TriangleSet's object id per lane.
};

/// A Bvh of at most this many blocks is queried without its nodes: every block is tested at once.
/// A 12-triangle box (two blocks) costs a node test and one or two block tests through its root;
/// the blocks alone save the node and the box test's constants, which for an instanced box are a
/// third of its cost (64 boxes, AO rays: 43 -> 53 Mrays/s).
inline constexpr std::size_t kDirectBlocks = 2;

/// The built hierarchy. nodes[0] is the root whenever the set has triangles; a leaf reference names
/// a run of blocks.
struct BvhLayout {
  AlignedVector<Node8> nodes;
  AlignedVector<LeafBlock> blocks;
  AccelStats stats;

  /// Whether queries test every block at once (1 to kDirectBlocks blocks) instead of walking the nodes.
  bool direct() const { return !blocks.empty() && blocks.size() <= kDirectBlocks; }
  /// The leaf reference naming every block (a direct Bvh's whole set).
  std::uint32_t all_blocks() const { return leaf_ref(0, static_cast<std::uint32_t>(blocks.size())); }
};

/// Closest hit in (tmin, tmax] (see Bvh::intersect). Thread-safe.
Hit intersect(const BvhLayout& bvh, const Ray& ray);
/// Any hit in (tmin, tmax] (see Bvh::occluded). Thread-safe.
bool occluded(const BvhLayout& bvh, const Ray& ray);
/// Rays whose walks a stream steps in turn (see occluded_stream, intersect_stream).
inline constexpr int kStreamWalks = 3;
inline constexpr int kClosestStreamWalks = 2;
/// occluded[i] = occluded(bvh, rays[i]) for every ray, bit for bit, the walks of kStreamWalks rays
/// stepped in turn so that their latencies overlap. Thread-safe.
void occluded_stream(const BvhLayout& bvh, std::span<const Ray> rays, std::uint8_t* occluded);
/// hits[i] = intersect(bvh, rays[i]) for every ray, bit for bit, kStreamWalks walks stepped in turn.
/// Thread-safe.
void intersect_stream(const BvhLayout& bvh, std::span<const Ray> rays, Hit* hits);
/// intersect(bvh, ray) by a counting traversal that adds its work to `counters`.
Hit intersect(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters);
/// occluded(bvh, ray) by a counting traversal that adds its work to `counters`.
bool occluded(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters);

}  // namespace vf::bvh
