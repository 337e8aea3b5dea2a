#pragma once
/// \file The exact BVH's layout for a GPU, host and device, no STL: 8-wide compressed nodes in the
/// spirit of Ylitie, Karras and Laine's CWBVH (HPG 2017) — each child box quantised to 8 bits a
/// coordinate relative to its parent's box, rounded outward, so a decoded box always contains the
/// box the CPU Bvh tests (conservative, hence exact) — and the triangles in one flat array in leaf
/// order. Built from the CPU Bvh's builder (gpu_bvh.hpp); traversed by bvh_traversal.hpp.

#include "visfield/core/host_device.hpp"
#include "visfield/core/ray.hpp"

namespace vf::gpu {

/// A slot's meta byte when the slot holds nothing.
inline constexpr unsigned char kEmptySlot = 0xff;
/// Most triangles one leaf (one slot) holds: its count takes 2 bits of the meta byte.
inline constexpr int kMaxLeafTriangles = 4;

/// One 8-wide node, 80 bytes. Child box k on axis a is [origin[a] + lo[a][k]·scale(a),
/// origin[a] + hi[a][k]·scale(a)] with scale(a) = 2^(exponent[a] − 127). Interior children are stored
/// consecutively from child_base in slot order; the triangles of the leaf slots consecutively from
/// triangle_base in slot order. meta[k]: kEmptySlot; for an interior slot (bit k of `interior`) the
/// child's offset from child_base; for a leaf slot (count − 1) << 5 | its first triangle's offset from
/// triangle_base.
struct alignas(16) WideNode {
  float origin[3];
  unsigned char exponent[3];
  unsigned char interior;
  unsigned int child_base;
  unsigned int triangle_base;
  unsigned char meta[8];
  unsigned char lo[3][8];
  unsigned char hi[3][8];
};
static_assert(sizeof(WideNode) == 80, "WideNode is 80 bytes");

/// One triangle of the flat array, 48 bytes (three 16-byte loads): its corners and its index in the
/// TriangleSet the BVH was built from (the tie-break of equal t, as the CPU Bvh and BruteForce break it).
struct alignas(16) WideTriangle {
  float p0[3];
  unsigned int index;
  float p1[3];
  unsigned int pad1;
  float p2[3];
  unsigned int pad2;
};
static_assert(sizeof(WideTriangle) == 48, "WideTriangle is 48 bytes");

/// What a traversal reads: borrowed pointers (host or device memory alike), valid as long as the
/// structure they come from. node_count 0: an empty structure (every query misses).
struct BvhView {
  const WideNode* nodes = nullptr;
  const WideTriangle* triangles = nullptr;
  const unsigned int* prim = nullptr;      ///< Triangle id in its mesh, by TriangleSet index.
  const unsigned int* instance = nullptr;  ///< Object id, by TriangleSet index.
  unsigned int node_count = 0;
  /// Most entries a traversal stack ever holds in this tree: over root-to-node paths, the sum of each
  /// node's children less one (a node walks one child and pushes the rest). 0 for an empty tree.
  unsigned int stack_bound = 0;
};

/// Node `i` read whole: on a device as five 16-byte loads through the read-only cache (the fields
/// are then taken from registers, not read a byte at a time from memory), on the host a plain copy.
VF_HOST_DEVICE inline WideNode load_node(const WideNode* nodes, unsigned int i) {
#if defined(__CUDA_ARCH__)
  union {
    uint4 v[5];
    WideNode node;
  } out;
  const uint4* src = reinterpret_cast<const uint4*>(nodes + i);
  VF_UNROLL
  for (int k = 0; k < 5; ++k) out.v[k] = __ldg(src + k);
  return out.node;
#else
  return nodes[i];
#endif
}

/// Triangle `i` read whole: three 16-byte loads on a device, a plain copy on the host.
VF_HOST_DEVICE inline WideTriangle load_triangle(const WideTriangle* triangles, unsigned int i) {
#if defined(__CUDA_ARCH__)
  union {
    uint4 v[3];
    WideTriangle triangle;
  } out;
  const uint4* src = reinterpret_cast<const uint4*>(triangles + i);
  VF_UNROLL
  for (int k = 0; k < 3; ++k) out.v[k] = __ldg(src + k);
  return out.triangle;
#else
  return triangles[i];
#endif
}

/// 2^(e − 127) for a biased exponent e in [1, 254], exactly (the float with that exponent field).
VF_HOST_DEVICE inline float exponent_scale(unsigned int e) {
  const unsigned int bits = e << 23;
#if defined(__CUDA_ARCH__)
  return __uint_as_float(bits);
#else
  float f;
  __builtin_memcpy(&f, &bits, sizeof f);
  return f;
#endif
}

/// A quantised coordinate decoded: origin + q·scale, in this order (q·scale is exact), host and
/// device alike; the builder checks its rounding against the box it stands for.
VF_HOST_DEVICE inline float decode(float origin, unsigned int q, float scale) { return origin + static_cast<float>(q) * scale; }

/// A leaf's reference on a traversal stack: bit 31 set, count − 1 in bits 27..30, first triangle
/// below; an interior reference is the node's index (bit 31 clear).
inline constexpr unsigned int kLeafBit = 0x80000000u;
/// The stack reference of a leaf of `count` (1..16) triangles from triangle `first` (< 2^27).
VF_HOST_DEVICE inline unsigned int leaf_reference(unsigned int first, unsigned int count) {
  return kLeafBit | ((count - 1u) << 27) | first;
}

}  // namespace vf::gpu
