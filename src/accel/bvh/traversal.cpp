// Single-ray traversal of the 8-wide triangle BVH: closest hit and any hit. Boxes are tested
// conservatively (box_test.hpp) and padded (collapse.cpp); leaves run the same block test as
// BruteForce, and among equal t the lowest TriangleSet index wins, so closest hits are the oracle's
// (ties included) whenever the triangle test's rounding keeps a computed hit inside the padded boxes.
// A kernel file: compiled once per instruction set (src/core/isa_dispatch.hpp).

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <optional>
#include <span>

#include "bvh/bvh_walks.hpp"
#include "core/isa_dispatch.hpp"

namespace vf::isa_avx512 {
void bvh_occluded_stream(const bvh::BvhLayout& bvh, std::span<const Ray> rays, std::uint8_t* occluded);
void bvh_intersect_stream(const bvh::BvhLayout& bvh, std::span<const Ray> rays, Hit* hits);
Hit bvh_intersect(const bvh::BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters);
bool bvh_occluded(const bvh::BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters);
}  // namespace vf::isa_avx512

namespace vf::bvh {
namespace {

template <bool kCount>
Hit closest_hit(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  if constexpr (kCount) ++counters->rays;
  // An invalid ray (NaN, infinite, zero direction, tmin >= tmax) hits nothing; its NaN slab values
  // would pass every box test, the empty child slots' included.
  if (bvh.nodes.empty() || !ray.is_valid()) return Hit{};
  if (bvh.direct()) return closest_hit_direct<kCount>(bvh, ray, counters);
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
  if (bvh.nodes.empty() || !ray.is_valid()) return false;  // as closest_hit()
  if (bvh.direct()) return any_hit_direct<kCount>(bvh, ray, counters);
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
  VF_USE_WIDER(bvh_occluded_stream, bvh, rays, occluded);
  if (bvh.direct()) {
    for (std::size_t i = 0; i < rays.size(); ++i) occluded[i] = rays[i].is_valid() && any_hit_direct<false>(bvh, rays[i], nullptr) ? 1 : 0;
    return;
  }
  struct Walk {
    BvhAnyHit through;
    AnyHitState::Step last = AnyHitState::Step::going;
  };
  with_traversal_rays(rays, [&](std::size_t first, std::size_t count, const std::optional<TraversalRay>* traversal_rays) {
    interleave_walks<Walk, kStreamWalks>(
        count,
        [&](Walk& w, std::size_t i) {
          w.through.start(bvh, rays[first + i], *traversal_rays[i]);
          return true;
        },
        [](Walk& w) { return (w.last = w.through.step()) == AnyHitState::Step::going; },
        [&](const Walk& w, std::size_t i) { occluded[first + i] = w.last == AnyHitState::Step::hit ? 1 : 0; });
  });
}

void intersect_stream(const BvhLayout& bvh, std::span<const Ray> rays, Hit* hits) {
  VF_USE_WIDER(bvh_intersect_stream, bvh, rays, hits);
  if (bvh.nodes.empty() || kMeasureCut == 1) {
    std::fill(hits, hits + rays.size(), Hit{});
    return;
  }
  if (bvh.direct()) {
    for (std::size_t i = 0; i < rays.size(); ++i) std::construct_at(&hits[i], closest_hit_direct<false>(bvh, rays[i], nullptr));
    return;
  }
  struct Walk {
    const TraversalRay* ray = nullptr;
    std::optional<TriangleLeaves<false>> leaves;
    ClosestHitState state;
    std::size_t item = 0;  // the ray's place in its run
  };
  const Node8& root = bvh.nodes[0];
  with_traversal_rays(rays, [&](std::size_t first, std::size_t count, const std::optional<TraversalRay>* traversal_rays) {
    // The rays that meet none of the root's boxes (half of random segments through a scene's bounding
    // sphere) end here, in a loop without branches: their walks would end at the root after a
    // mispredicted branch each. The others' walks test the root again, from the first-level cache.
    std::array<std::uint8_t, kTraversalRun> live;
    std::size_t walks = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const Ray& ray = rays[first + i];
      V8 unused;
      const simd::LaneBits lanes = test_children(root, traversal_rays[i]->box, V8::broadcast(widen_down(ray.tmin)),
                                                 V8::broadcast(widen_up(ray.tmax)), unused);
      std::construct_at(&hits[first + i], Hit{});
      live[walks] = static_cast<std::uint8_t>(i);
      walks += lanes != 0 && ray.is_valid() ? 1 : 0;  // an invalid ray hits nothing (closest_hit())
    }
    interleave_walks<Walk, kClosestStreamWalks>(
        walks,
        [&](Walk& w, std::size_t k) {
          const std::size_t i = live[k];
          const Ray& ray = rays[first + i];
          w.ray = &*traversal_rays[i];
          w.leaves.emplace(bvh, *w.ray, ray.tmin, ray.tmax, nullptr);
          w.state.start(ray.tmin, ray.tmax);
          w.item = i;
          return true;
        },
        [&](Walk& w) {
          if constexpr (kMeasureCut == 2) return false;
          return w.state.step(bvh.nodes.data(), w.ray->box, [&](std::uint32_t ref, float& best_t) { return w.leaves->closest(ref, best_t); },
                              IgnoreNodes{});
        },
        [&](const Walk& w, std::size_t) { hits[first + w.item] = w.leaves->hit(); });
  });
}

Hit intersect(const BvhLayout& bvh, const Ray& ray) {
  VF_USE_WIDER(bvh_intersect, bvh, ray, nullptr);
  return closest_hit<false>(bvh, ray, nullptr);
}
bool occluded(const BvhLayout& bvh, const Ray& ray) {
  VF_USE_WIDER(bvh_occluded, bvh, ray, nullptr);
  return any_hit<false>(bvh, ray, nullptr);
}
Hit intersect(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  VF_USE_WIDER(bvh_intersect, bvh, ray, counters);
  return closest_hit<true>(bvh, ray, counters);
}
bool occluded(const BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  VF_USE_WIDER(bvh_occluded, bvh, ray, counters);
  return any_hit<true>(bvh, ray, counters);
}

}  // namespace vf::bvh

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void bvh_occluded_stream(const bvh::BvhLayout& bvh, std::span<const Ray> rays, std::uint8_t* occluded) {
  bvh::occluded_stream(bvh, rays, occluded);
}
VF_WIDER_ENTRY void bvh_intersect_stream(const bvh::BvhLayout& bvh, std::span<const Ray> rays, Hit* hits) { bvh::intersect_stream(bvh, rays, hits); }
VF_WIDER_ENTRY Hit bvh_intersect(const bvh::BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  return counters ? bvh::intersect(bvh, ray, counters) : bvh::intersect(bvh, ray);
}
VF_WIDER_ENTRY bool bvh_occluded(const bvh::BvhLayout& bvh, const Ray& ray, BvhQueryCounters* counters) {
  return counters ? bvh::occluded(bvh, ray, counters) : bvh::occluded(bvh, ray);
}
}  // namespace vf::isa_avx512
#endif
