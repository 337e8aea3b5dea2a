// Single-ray traversal of the 8-wide triangle BVH: closest hit and any hit. Boxes are tested
// conservatively (box_test.hpp) and padded (collapse.cpp); leaves run the same block test as
// BruteForce, and among equal t the lowest TriangleSet index wins, so closest hits are the oracle's
// (ties included) whenever the triangle test's rounding keeps a computed hit inside the padded boxes.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <optional>
#include <span>

#include "bvh/bvh_walks.hpp"

namespace vf::bvh {
namespace {

template <bool kCount>
Hit closest_hit(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  if constexpr (kCount) ++counters->rays;
  if (bvh.nodes.empty()) return Hit{};
  const TraversalRay traversal_ray(ray);
  TriangleLeaves<kCount> leaves(bvh, traversal_ray, ray.tmin, ray.tmax, counters);
  const auto visit = [&](std::uint32_t ref, float& best_t) { return leaves.closest(ref, best_t); };
  if constexpr (kCount)
    closest_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, visit, [&] { ++counters->nodes; });
  else
    closest_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, visit);
  return leaves.hit();
}

template <bool kCount>
bool any_hit(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  if constexpr (kCount) ++counters->rays;
  if (bvh.nodes.empty()) return false;
  const TraversalRay traversal_ray(ray);
  const TriangleLeaves<kCount> leaves(bvh, traversal_ray, ray.tmin, ray.tmax, counters);
  const auto test = [&](std::uint32_t ref) { return leaves.any(ref); };
  if constexpr (kCount)
    return any_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, test, [&] { ++counters->nodes; });
  else
    return any_hit_walk(bvh.nodes.data(), traversal_ray.box, ray.tmin, ray.tmax, test);
}

}  // namespace

void occluded_stream(const BvhLayout& bvh, std::span<const Ray> rays, std::uint8_t* occluded) {
  // One ray's walk is a chain of dependent loads and compares (a node's boxes, then the child they
  // pick); several rays' walks stepped in turn keep the core busy while each waits.
  struct Slot {
    BvhAnyHit walk;
    std::size_t index = 0;
    bool live = false;
  };
  std::array<Slot, kStreamWalks> slots;
  std::size_t next = 0;
  const auto start = [&](Slot& slot) {
    if (next == rays.size()) return false;
    slot.walk.start(bvh, rays[next]);
    slot.index = next++;
    return true;
  };
  int live = 0;
  for (Slot& slot : slots) live += (slot.live = start(slot)) ? 1 : 0;
  while (live > 0) {
    for (Slot& slot : slots) {
      if (!slot.live) continue;
      const AnyHitState::Step step = slot.walk.step();
      if (step == AnyHitState::Step::going) continue;
      occluded[slot.index] = step == AnyHitState::Step::hit ? 1 : 0;
      if (!(slot.live = start(slot))) --live;
    }
  }
}

void intersect_stream(const BvhLayout& bvh, std::span<const Ray> rays, Hit* hits) {
  if (bvh.nodes.empty()) {
    std::fill(hits, hits + rays.size(), Hit{});
    return;
  }
  // As occluded_stream: several rays' walks stepped in turn.
  struct Slot {
    std::optional<TraversalRay> ray;
    std::optional<TriangleLeaves<false>> leaves;
    ClosestHitState walk;
    std::size_t index = 0;
    bool live = false;
  };
  std::array<Slot, kClosestStreamWalks> slots;
  std::size_t next = 0;
  const auto start = [&](Slot& slot) {
    if (next == rays.size()) return false;
    const Ray& ray = rays[next];
    slot.ray.emplace(ray);
    slot.leaves.emplace(bvh, *slot.ray, ray.tmin, ray.tmax, nullptr);
    slot.walk.start(ray.tmin, ray.tmax);
    slot.index = next++;
    return true;
  };
  int live = 0;
  for (Slot& slot : slots) live += (slot.live = start(slot)) ? 1 : 0;
  while (live > 0) {
    for (Slot& slot : slots) {
      if (!slot.live) continue;
      const auto visit = [&](std::uint32_t ref, float& best_t) { return slot.leaves->closest(ref, best_t); };
      if (slot.walk.step(bvh.nodes.data(), slot.ray->box, visit, IgnoreNodes{})) continue;
      std::construct_at(&hits[slot.index], slot.leaves->hit());
      if (!(slot.live = start(slot))) --live;
    }
  }
}

Hit intersect(const BvhLayout& bvh, const Ray& ray) { return closest_hit<false>(bvh, ray, nullptr); }
bool occluded(const BvhLayout& bvh, const Ray& ray) { return any_hit<false>(bvh, ray, nullptr); }
Hit intersect(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) { return closest_hit<true>(bvh, ray, counters); }
bool occluded(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) { return any_hit<true>(bvh, ray, counters); }

}  // namespace vf::bvh
