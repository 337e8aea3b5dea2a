// Queries of the instance layer: the top level's 8-wide traversal (shared with the Bvh) whose leaves
// map the ray into each object's space and ask the object's mesh structure.

#include <array>

#include <tbb/blocked_range.h>

#include "bvh/box_test.hpp"
#include "bvh/bvh_walks.hpp"
#include "bvh/wide_traversal.hpp"
#include "instances/instance_layout.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"

namespace vf {
namespace {

bvh::BoxRay box_ray(const Ray& ray) {
  const float inv[3] = {1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z};  // +-inf for +-0
  bvh::BoxRay box;
  box.set(ray, inv);
  return box;
}

const instances::PlacedObject* leaf_objects(const instances::InstanceLayout& layout, std::uint32_t ref,
                                            const instances::PlacedObject*& end) {
  const instances::PlacedObject* first = layout.placed.data() + bvh::leaf_first_item(ref);
  end = first + bvh::leaf_item_count(ref);
  return first;
}

}  // namespace

Hit InstanceLayer::intersect(const Ray& ray) const {
  const instances::InstanceLayout& layout = *layout_;
  if (layout.nodes.empty()) return Hit{};
  Hit best;
  bvh::closest_hit_walk(layout.nodes.data(), box_ray(ray), ray.tmin, ray.tmax, [&](std::uint32_t ref, float& best_t) {
    bool improved = false;
    const instances::PlacedObject* end = nullptr;
    for (const instances::PlacedObject* o = leaf_objects(layout, ref, end); o != end; ++o) {
      Ray local = o->to_object.apply(ray);
      local.tmax = best_t;
      const Hit hit = std::visit([&](const auto& mesh) { return mesh.intersect(local); }, *o->mesh);
      // hit.t <= best_t; an equal t goes to the lower object id.
      if (!hit || !(hit.t < best_t || o->id < best.instance)) continue;
      best = hit;
      best.instance = o->id;
      if (!o->to_object.identity) best.normal = o->to_world.apply_normal(hit.normal);
      best_t = hit.t;
      improved = true;
    }
    return improved;
  });
  return best;
}

bool InstanceLayer::occluded(const Ray& ray) const {
  const instances::InstanceLayout& layout = *layout_;
  if (layout.nodes.empty()) return false;
  return bvh::any_hit_walk(layout.nodes.data(), box_ray(ray), ray.tmin, ray.tmax, [&](std::uint32_t ref) {
    const instances::PlacedObject* end = nullptr;
    for (const instances::PlacedObject* o = leaf_objects(layout, ref, end); o != end; ++o) {
      const Ray local = o->to_object.apply(ray);
      if (std::visit([&](const auto& mesh) { return mesh.occluded(local); }, *o->mesh)) return true;
    }
    return false;
  });
}

void occluded_block(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  const instances::InstanceLayout& layout = *layer.layout_;
  if (layout.nodes.empty()) {
    std::fill(occluded.begin(), occluded.end(), std::uint8_t{0});
    return;
  }
  // A ray's walk: the top level's any-hit walk; a leaf it reaches hands over its objects, whose Bvh
  // walks are stepped in the same turns, one object after another, before the top level goes on.
  struct Slot {
    const Ray* ray = nullptr;
    bvh::BoxRay box;
    bvh::AnyHitState top;
    bool top_done = false;                                  // the top level's stack is empty
    const instances::PlacedObject *object = nullptr, *end = nullptr;  // the leaf's objects left
    bvh::BvhAnyHit inside;                                  // the walk in *object's Bvh
    bool in_object = false;
    std::size_t index = 0;
    bool live = false;
  };
  constexpr int kWalks = bvh::kStreamWalks;
  std::array<Slot, kWalks> slots;
  std::size_t next = 0;
  const auto start = [&](Slot& slot) {
    if (next == rays.size()) return false;
    slot.ray = &rays[next];
    slot.box = box_ray(*slot.ray);
    slot.top.start(slot.ray->tmin, slot.ray->tmax);
    slot.top_done = slot.in_object = false;
    slot.object = slot.end = nullptr;
    slot.index = next++;
    return true;
  };
  // Enters the next object of the slot's leaf whose Bvh walk is stepped; answers the others (small
  // Bvhs, meshes of other structures) at once. Returns true when one of those was hit.
  const auto enter_object = [&](Slot& slot) {
    for (; slot.object != slot.end; ++slot.object) {
      const Ray local = slot.object->to_object.apply(*slot.ray);
      // A Bvh of one node (a few leaves under the root) is answered at once: stepping it would cost
      // more in switching between walks than its latency (10,000 boxes of 12 triangles: -10%).
      const Bvh* mesh = std::get_if<Bvh>(slot.object->mesh);
      if (mesh && mesh->layout_->nodes.size() > 1) {
        slot.inside.start(*mesh->layout_, local);
        slot.in_object = true;
        return false;
      }
      if (std::visit([&](const auto& mesh) { return mesh.occluded(local); }, *slot.object->mesh)) return true;
    }
    slot.in_object = false;
    return false;
  };
  // One step of the slot: a node or leaf of the top level, or of the object's Bvh it is in.
  enum class Answer { pending, hit, miss };
  const auto step = [&](Slot& slot) {
    if (slot.in_object) {
      const bvh::AnyHitState::Step inside = slot.inside.step();
      if (inside == bvh::AnyHitState::Step::going) return Answer::pending;
      if (inside == bvh::AnyHitState::Step::hit) return Answer::hit;
      ++slot.object;
    } else {
      const bvh::AnyHitState::Step top = slot.top.step(layout.nodes.data(), slot.box, [&](std::uint32_t ref) {
        slot.object = leaf_objects(layout, ref, slot.end);
        return false;  // its objects are walked in the next steps
      }, bvh::IgnoreNodes{});
      slot.top_done = top == bvh::AnyHitState::Step::miss;
    }
    if (enter_object(slot)) return Answer::hit;
    if (slot.in_object || !slot.top_done) return Answer::pending;
    return Answer::miss;
  };
  int live = 0;
  for (Slot& slot : slots) live += (slot.live = start(slot)) ? 1 : 0;
  while (live > 0) {
    for (Slot& slot : slots) {
      if (!slot.live) continue;
      const Answer answer = step(slot);
      if (answer == Answer::pending) continue;
      occluded[slot.index] = answer == Answer::hit ? 1 : 0;
      if (!(slot.live = start(slot))) --live;
    }
  }
}

void occluded_batch(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    check_interrupt();
    occluded_block(layer, rays.subspan(range.begin(), range.size()), occluded.subspan(range.begin(), range.size()));
  });
}

}  // namespace vf
