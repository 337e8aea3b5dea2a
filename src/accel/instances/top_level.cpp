// Queries of the instance layer: the top level's 8-wide traversal (shared with the Bvh) whose leaves
// map the ray into each object's space and ask the object's mesh structure. A kernel file: compiled
// once per instruction set (src/core/isa_dispatch.hpp).

#include <tbb/blocked_range.h>

#include "bvh/box_test.hpp"
#include "bvh/bvh_walks.hpp"
#include "bvh/wide_traversal.hpp"
#include "core/isa_dispatch.hpp"
#include "instances/instance_layout.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::isa_avx512 {
Hit instances_intersect(const InstanceLayer& layer, const Ray& ray);
bool instances_occluded(const InstanceLayer& layer, const Ray& ray);
void occluded_block(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
void occluded_batch(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
}  // namespace vf::isa_avx512

namespace vf {
namespace {

bvh::BoxRay box_ray(const Ray& ray) {
  const float inv[3] = {bvh::box_reciprocal(ray.dir.x), bvh::box_reciprocal(ray.dir.y), bvh::box_reciprocal(ray.dir.z)};
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
  VF_USE_WIDER(instances_intersect, *this, ray);
  const instances::InstanceLayout& layout = *layout_;
  if (layout.nodes.empty() || !ray.is_valid()) return Hit{};  // NaN slab values would pass every box test
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
  VF_USE_WIDER(instances_occluded, *this, ray);
  const instances::InstanceLayout& layout = *layout_;
  if (layout.nodes.empty() || !ray.is_valid()) return false;
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
  VF_USE_WIDER(occluded_block, layer, rays, occluded);
  const instances::InstanceLayout& layout = *layer.layout_;
  if (layout.nodes.empty()) {
    std::fill(occluded.begin(), occluded.end(), std::uint8_t{0});
    return;
  }
  // A ray's walk: the top level's any-hit walk; a leaf it reaches hands over its objects, whose Bvh
  // walks are stepped in the same turns, one object after another, before the top level goes on.
  enum class Answer { pending, hit, miss };
  struct Walk {
    const Ray* ray = nullptr;
    bvh::BoxRay box;
    bvh::AnyHitState top;
    bool top_done = false;                                              // the top level's stack is empty
    const instances::PlacedObject *object = nullptr, *end = nullptr;  // the leaf's objects left
    bvh::BvhAnyHit inside;                                              // the walk in *object's Bvh
    bool in_object = false;
    Answer answer = Answer::pending;
  };
  // Enters the next object of the walk's leaf whose mesh is a Bvh, whose walk is stepped; answers
  // the others (meshes of other structures) at once. Returns true when one of those was hit.
  const auto enter_object = [&](Walk& w) {
    if constexpr (bvh::kMeasureCut == 3) w.object = w.end;
    for (; w.object != w.end; ++w.object) {
      const Ray local = w.object->to_object.apply(*w.ray);
      // A Bvh walk is stepped: since a ray's constants are computed without branches, answering
      // even a one-node walk at once costs more than switching walks (64 boxes of 12 triangles:
      // +7%). A direct Bvh (its blocks without a node or box constants) is answered at once: that
      // took 64 boxes from 0.82x to 1.00x Embree's instancing, where stepping its test in turn
      // measured 0.94-0.97x.
      if (const Bvh* mesh = std::get_if<Bvh>(w.object->mesh)) {
        if (mesh->layout_->direct()) {
          if (bvh::any_hit_direct<false>(*mesh->layout_, local, nullptr)) return true;
          continue;
        }
        w.inside.start(*mesh->layout_, local);
        w.in_object = true;
        return false;
      }
      if (std::visit([&](const auto& m) { return m.occluded(local); }, *w.object->mesh)) return true;
    }
    w.in_object = false;
    return false;
  };
  // One step: a node or leaf of the top level, or of the object's Bvh the walk is in.
  const auto step = [&](Walk& w) {
    if (w.in_object) {
      const bvh::AnyHitState::Step inside = w.inside.step();
      if (inside == bvh::AnyHitState::Step::going) return Answer::pending;
      if (inside == bvh::AnyHitState::Step::hit) return Answer::hit;
      ++w.object;
    } else {
      const bvh::AnyHitState::Step top = w.top.step(layout.nodes.data(), w.box, [&](std::uint32_t ref) {
        w.object = leaf_objects(layout, ref, w.end);
        return false;  // its objects are walked in the next steps
      }, bvh::IgnoreNodes{});
      w.top_done = top == bvh::AnyHitState::Step::miss;
    }
    if (enter_object(w)) return Answer::hit;
    if (w.in_object || !w.top_done) return Answer::pending;
    return Answer::miss;
  };
  bvh::interleave_walks<Walk, bvh::kStreamWalks>(
      rays.size(),
      [&](Walk& w, std::size_t i) {
        if (!rays[i].is_valid()) {  // hits nothing, and takes no walk
          occluded[i] = 0;
          return false;
        }
        w.ray = &rays[i];
        w.box = box_ray(rays[i]);
        w.top.start(rays[i].tmin, rays[i].tmax);
        w.top_done = w.in_object = false;
        w.object = w.end = nullptr;
        return true;
      },
      [&](Walk& w) { return (w.answer = step(w)) == Answer::pending; },
      [&](const Walk& w, std::size_t i) { occluded[i] = w.answer == Answer::hit ? 1 : 0; });
}

void occluded_batch(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  VF_USE_WIDER(occluded_batch, layer, rays, occluded);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
    check_interrupt();
    occluded_block(layer, rays.subspan(range.begin(), range.size()), occluded.subspan(range.begin(), range.size()));
  });
}

}  // namespace vf

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY Hit instances_intersect(const InstanceLayer& layer, const Ray& ray) { return layer.intersect(ray); }
VF_WIDER_ENTRY bool instances_occluded(const InstanceLayer& layer, const Ray& ray) { return layer.occluded(ray); }
VF_WIDER_ENTRY void occluded_block(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  vf::occluded_block(layer, rays, occluded);
}
VF_WIDER_ENTRY void occluded_batch(const InstanceLayer& layer, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  vf::occluded_batch(layer, rays, occluded);
}
}  // namespace vf::isa_avx512
#endif
