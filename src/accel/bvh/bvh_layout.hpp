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
using LeafBlock = simd::TriangleBlock<kLeafWidth>;

/// The built hierarchy. nodes[0] is the root whenever the set has triangles; a leaf reference names
/// a run of blocks.
struct BvhLayout {
  AlignedVector<Node8> nodes;
  AlignedVector<LeafBlock> blocks;
  std::vector<std::uint32_t> lane_triangle;  ///< TriangleSet index per block lane; kInvalidId in unused lanes.
  std::vector<std::uint32_t> prim;           ///< Copy of the TriangleSet's triangle ids.
  std::vector<ObjectId> instance;            ///< Copy of the TriangleSet's object ids.
  AccelStats stats;
};

/// Closest hit in (tmin, tmax] (see Bvh::intersect). Thread-safe.
Hit intersect(const BvhLayout& bvh, const Ray& ray);
/// Any hit in (tmin, tmax] (see Bvh::occluded). Thread-safe.
bool occluded(const BvhLayout& bvh, const Ray& ray);
/// Rays whose any-hit walks a stream steps in turn (see occluded_stream).
inline constexpr int kStreamWalks = 4;
/// occluded[i] = occluded(bvh, rays[i]) for every ray, bit for bit, the walks of kStreamWalks rays
/// stepped in turn so that their latencies overlap. Thread-safe.
void occluded_stream(const BvhLayout& bvh, std::span<const Ray> rays, std::uint8_t* occluded);
/// intersect(bvh, ray) by a counting traversal that adds its work to `counters`.
Hit intersect(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters);
/// occluded(bvh, ray) by a counting traversal that adds its work to `counters`.
bool occluded(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters);

}  // namespace vf::bvh
