// Queries of the instance layer: the top level's 8-wide traversal (shared with the Bvh) whose leaves
// map the ray into each object's space and ask the object's mesh structure.

#include "bvh/box_test.hpp"
#include "bvh/wide_traversal.hpp"
#include "instances/instance_layout.hpp"

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

}  // namespace vf
