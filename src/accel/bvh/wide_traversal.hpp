#pragma once
/// \file Single-ray traversal of 8-wide nodes, closest hit and any hit, generic over what a leaf holds
/// (private to the accel module): the Bvh's leaves test triangle blocks, the instance layer's top
/// level visits objects. The leaf visitor is inlined, so each owner gets a traversal of its own.

#include <array>
#include <bit>
#include <cstddef>
#include <type_traits>

#include "bvh/box_test.hpp"
#include "bvh/wide_nodes.hpp"
#include "visfield/core/lane_compress.hpp"

namespace vf::bvh {

/// No traversal stack holds more entries than this.
inline constexpr int kStackSize = 7 * kMaxBinaryDepth + 1;

/// A walk's hook on each interior node it tests: nothing, for the queries' own walks.
struct IgnoreNodes {
  void operator()() const {}
};

/// Runs the walks of items 0 .. count - 1, kWalks of them at a time stepped in turn, so that one
/// walk's chain of dependent loads and compares overlaps the others' work: `start(walk, i)` begins
/// item i in `walk` (false: the item needs no walk), `step(walk)` takes one step and returns true
/// while the walk goes on, `finish(walk, i)` takes the ended walk's answer.
template <class Walk, int kWalks, class Start, class Step, class Finish>
void interleave_walks(std::size_t count, Start&& start, Step&& step, Finish&& finish) {
  struct Slot {
    Walk walk;
    std::size_t item = 0;
    bool live = false;
  };
  std::array<Slot, kWalks> slots;
  std::size_t next = 0;
  const auto begin = [&](Slot& slot) {
    for (; next < count; ++next)
      if (start(slot.walk, next)) {
        slot.item = next++;
        return true;
      }
    return false;
  };
  int live = 0;
  for (Slot& slot : slots) live += (slot.live = begin(slot)) ? 1 : 0;
  while (live > 0) {
    for (Slot& slot : slots) {
      if (!slot.live || step(slot.walk)) continue;
      finish(slot.walk, slot.item);
      if (!(slot.live = begin(slot))) --live;
    }
  }
}

/// Returns the first child of `node` in `lanes` (tree order) and pushes the others, in order, on the
/// stack at stack[sp], so that the last one is popped first. Writes up to eight entries past the
/// new top (the stack has that much slack). `lanes` must be non-zero.
inline std::uint32_t descend_and_push(const Node8& node, simd::LaneBits lanes, std::uint32_t* stack, int& sp) {
#if defined(__AVX512VL__)
  // Compress in a register and store all eight lanes at once: a per-child loop would have its trip
  // count mispredicted at almost every node.
  const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
  const __m256i hit = _mm256_maskz_compress_epi32(static_cast<__mmask8>(lanes), children);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack + sp), _mm256_alignr_epi32(hit, hit, 1));
  sp += std::popcount(lanes) - 1;
  return static_cast<std::uint32_t>(_mm256_cvtsi256_si32(hit));
#elif defined(__AVX2__)
  // AVX2 has no compress: a permute by the mask's lane numbers does it, then another moves lanes
  // 1..7 down by one to be stored at once.
  const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
  const __m256i hit = _mm256_permutevar8x32_epi32(children, simd::compress_index8(lanes));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack + sp), _mm256_permutevar8x32_epi32(hit, _mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 7)));
  sp += std::popcount(lanes) - 1;
  return static_cast<std::uint32_t>(_mm256_cvtsi256_si32(hit));
#else
  const std::uint32_t first = node.child[simd::first_lane(lanes)];
  for (lanes &= lanes - 1; lanes != 0; lanes &= lanes - 1) stack[sp++] = node.child[simd::first_lane(lanes)];
  return first;
#endif
}

/// An any-hit walk taken one node or leaf at a time: any_hit_walk() runs one to its end; a stream of
/// rays steps several in turn so that their latencies overlap. Children are visited in tree order,
/// without sorting and without distances on the stack.
///
/// Measured on AO rays (bun_zipper, sponza, conference), near-to-far orders (sorted by entry
/// distance, or by the split planes) were slower: the first occluder found ends the query, and the
/// subtrees nearest the origin are often the surface the ray leaves.
class AnyHitState {
 public:
  /// Where a walk stands after a step.
  enum class Step { going, hit, miss };

  /// A walk from the root for a ray whose interval is [tmin, tmax].
  void start(float tmin, float tmax) {
    box_tmin_ = V8::broadcast(widen_down(tmin));
    box_tmax_ = V8::broadcast(widen_up(tmax));
    sp_ = 0;
    ref_ = node_ref(0);
  }
  /// Tests the next node's children (`on_node()` runs) or leaf (`test_leaf(ref)`, true when it found a
  /// hit, which ends the walk). `nodes` must hold the root.
  template <class TestLeaf, class OnNode>
  Step step(const Node8* nodes, const BoxRay& box, TestLeaf&& test_leaf, OnNode&& on_node) {
    if (is_leaf(ref_)) {
      if (test_leaf(ref_)) return Step::hit;
    } else {
      // Entry distances are not needed: any hit ends the walk, whatever its distance.
      V8 unused;
      on_node();
      const Node8& node = node_at(nodes, ref_);
      if (const simd::LaneBits lanes = test_children(node, box, box_tmin_, box_tmax_, unused)) {
        ref_ = descend_and_push(node, lanes, stack_.data(), sp_);
        return Step::going;
      }
    }
    if (sp_ == 0) return Step::miss;
    ref_ = stack_[--sp_];
    return Step::going;
  }

 private:
  V8 box_tmin_, box_tmax_;
  std::array<std::uint32_t, kStackSize + 8> stack_;
  int sp_ = 0;
  std::uint32_t ref_ = 0;
};

/// Any hit: the AnyHitState walk run to its end. `test_leaf(ref)` tests the leaf `ref` and returns
/// true when it found a hit. Returns whether a leaf did. `nodes` must hold the root. `on_node()` runs
/// at each interior node tested.
template <class TestLeaf, class OnNode = IgnoreNodes>
bool any_hit_walk(const Node8* nodes, const BoxRay& box, float tmin, float tmax, TestLeaf&& test_leaf, OnNode&& on_node = {}) {
  AnyHitState walk;
  walk.start(tmin, tmax);
  for (;;) {
    const AnyHitState::Step step = walk.step(nodes, box, test_leaf, on_node);
    if (step != AnyHitState::Step::going) return step == AnyHitState::Step::hit;
  }
}

/// A closest-hit walk taken one node or leaf at a time (closest_hit_walk() runs one to its end; a
/// stream steps several in turn): children are visited near to far, and subtrees whose entry
/// distance exceeds the closest hit so far are skipped.
class ClosestHitState {
 public:
  /// A walk from the root for a ray whose interval is [tmin, tmax].
  void start(float tmin, float tmax) {
    box_tmin_ = V8::broadcast(widen_down(tmin));
    best_t_ = tmax;
    cull_t_ = widen_up(tmax);
    box_tmax_ = V8::broadcast(cull_t_);
    sp_ = 0;
    ref_ = node_ref(0);
  }
  /// Tests the next node's children (`on_node()` runs) or leaf: `visit_leaf(ref, best_t)` tests the
  /// leaf `ref` against [tmin, best_t] and returns true when it lowered best_t. Returns false when
  /// the walk is over. `nodes` must hold the root.
  template <class VisitLeaf, class OnNode>
  bool step(const Node8* nodes, const BoxRay& box, VisitLeaf&& visit_leaf, OnNode&& on_node) {
    if (!is_leaf(ref_)) {
      on_node();
      const Node8& node = node_at(nodes, ref_);
      V8 t_near;
      simd::LaneBits lanes = test_children(node, box, box_tmin_, box_tmax_, t_near);
      if (lanes != 0) {
        alignas(32) float dist[8];
        t_near.store(dist);
        const int first = simd::first_lane(lanes);
        lanes &= lanes - 1;
        if (lanes == 0) {
          ref_ = node.child[first];
          return true;
        }
        const int second = simd::first_lane(lanes);
        lanes &= lanes - 1;
        if (lanes == 0) {
          // Two children: descend into the nearer, push the farther.
          const bool swap = dist[second] < dist[first];
          const int near = swap ? second : first, far = swap ? first : second;
          stack_[sp_++] = {node.child[far], dist[far]};
          ref_ = node.child[near];
          return true;
        }
        // Three or more: sort by entry distance, push far to near, descend into the nearest.
#if defined(__AVX2__)
        ref_ = sort_and_push(node, t_near, lanes | (1u << first) | (1u << second));
        return true;
#else
        Entry hits[8];
        hits[0] = {node.child[first], dist[first]};
        hits[1] = {node.child[second], dist[second]};
        int count = 2;
        for (; lanes != 0; lanes &= lanes - 1) {
          const int l = simd::first_lane(lanes);
          hits[count++] = {node.child[l], dist[l]};
        }
        for (int i = 1; i < count; ++i) {
          const Entry e = hits[i];
          int j = i;
          for (; j > 0 && hits[j - 1].t_near > e.t_near; --j) hits[j] = hits[j - 1];
          hits[j] = e;
        }
        for (int i = count - 1; i > 0; --i) stack_[sp_++] = hits[i];
        ref_ = hits[0].ref;
        return true;
#endif
      }
    } else if (visit_leaf(ref_, best_t_)) {
      cull_t_ = widen_up(best_t_);
      box_tmax_ = V8::broadcast(cull_t_);
    }
    // Next subtree from the stack that can still hold a hit.
    do {
      if (sp_ == 0) return false;
      --sp_;
    } while (stack_[sp_].t_near > cull_t_);
    ref_ = stack_[sp_].ref;
    return true;
  }

 private:
  struct Entry {
    std::uint32_t ref;
    float t_near;
  };
#if defined(__AVX2__)
  // Sorts the children in `lanes` by entry distance without branches (an odd-even merge network of 8
  // keys: the distance's bits with the lane in the 3 lowest, so equal distances keep tree order and
  // the order is near to far up to those bits, which only order, never cull), pushes all but the
  // nearest far to near (eight entries stored, the stack has the slack) and returns the nearest.
  // Blends, unpacks and permutes of AVX2 alone, but for one mask move and one interleave on AVX-512.
  std::uint32_t sort_and_push(const Node8& node, const V8& t_near, simd::LaneBits lanes) {
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    __m256i key = _mm256_or_si256(_mm256_and_si256(_mm256_castps_si256(t_near.v), _mm256_set1_epi32(~7)), lane);
    // Missed lanes last.
#if defined(__AVX512VL__)
    key = _mm256_mask_mov_epi32(_mm256_set1_epi32(-1), static_cast<__mmask8>(lanes), key);
#else
    const __m256i bit = _mm256_sllv_epi32(_mm256_set1_epi32(1), lane);
    const __m256i met = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(lanes)), bit), bit);
    key = _mm256_blendv_epi8(_mm256_set1_epi32(-1), key, met);
#endif
    const auto layer = [&](__m256i partner, auto max_lanes) {
      const __m256i other = _mm256_permutevar8x32_epi32(key, partner);
      key = _mm256_blend_epi32(_mm256_min_epu32(key, other), _mm256_max_epu32(key, other), decltype(max_lanes)::value);
    };
    layer(_mm256_setr_epi32(1, 0, 3, 2, 5, 4, 7, 6), std::integral_constant<int, 0xaa>{});
    layer(_mm256_setr_epi32(2, 3, 0, 1, 6, 7, 4, 5), std::integral_constant<int, 0xcc>{});
    layer(_mm256_setr_epi32(0, 2, 1, 3, 4, 6, 5, 7), std::integral_constant<int, 0x44>{});
    layer(_mm256_setr_epi32(4, 5, 6, 7, 0, 1, 2, 3), std::integral_constant<int, 0xf0>{});
    layer(_mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7), std::integral_constant<int, 0x30>{});
    layer(_mm256_setr_epi32(0, 2, 1, 4, 3, 6, 5, 7), std::integral_constant<int, 0x54>{});
    const __m256i order = _mm256_and_si256(key, _mm256_set1_epi32(7));
    const int count = std::popcount(lanes);
    // Stack entries i = 0 .. count - 2 are the sorted children count - 1 - i: far to near.
    const __m256i far_first = _mm256_permutevar8x32_epi32(order, _mm256_sub_epi32(_mm256_set1_epi32(count - 1), lane));
    const __m256i children = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
    const __m256i refs = _mm256_permutevar8x32_epi32(children, far_first);
    const __m256i dists = _mm256_permutevar8x32_epi32(_mm256_castps_si256(t_near.v), far_first);
#if defined(__AVX512F__)
    const __m512i entries = _mm512_permutex2var_epi32(_mm512_castsi256_si512(refs),
                                                      _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23),
                                                      _mm512_castsi256_si512(dists));
    _mm512_storeu_si512(stack_.data() + sp_, entries);
#else
    // (ref, distance) pairs: the unpacks interleave within 128-bit halves, the permutes put them in order.
    const __m256i low = _mm256_unpacklo_epi32(refs, dists), high = _mm256_unpackhi_epi32(refs, dists);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack_.data() + sp_), _mm256_permute2x128_si256(low, high, 0x20));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(stack_.data() + sp_ + 4), _mm256_permute2x128_si256(low, high, 0x31));
#endif
    sp_ += count - 1;
    return node.child[_mm256_cvtsi256_si32(order)];
  }
#endif

  V8 box_tmin_, box_tmax_;
  float best_t_ = 0.0f, cull_t_ = 0.0f;
  std::array<Entry, kStackSize + 8> stack_;
  int sp_ = 0;
  std::uint32_t ref_ = 0;
};

/// Closest hit: the ClosestHitState walk run to its end. `visit_leaf(ref, best_t)` tests the leaf
/// `ref` against [tmin, best_t] (best_t starts at tmax) and returns true when it lowered best_t.
/// `nodes` must hold the root. `on_node()` runs at each interior node tested.
template <class VisitLeaf, class OnNode = IgnoreNodes>
void closest_hit_walk(const Node8* nodes, const BoxRay& box, float tmin, float tmax, VisitLeaf&& visit_leaf, OnNode&& on_node = {}) {
  ClosestHitState walk;
  walk.start(tmin, tmax);
  while (walk.step(nodes, box, visit_leaf, on_node)) {
  }
}

}  // namespace vf::bvh
