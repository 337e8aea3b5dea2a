#include "visfield/registry/structure.hpp"

#include <utility>

#include "visfield/core/error.hpp"
#include "visfield/registry/scene_geometry.hpp"
#include "visfield/registry/structure_queries.hpp"

namespace vf {

Structure Structure::build(const Scene& scene, std::string_view spec, const BuildContext& context) {
  if (scene.instances().empty() || scene.instanced_triangle_count() == 0) throw Error("build: the scene has no triangles");
  SceneGeometry geometry(scene);
  return Structure(build_structure(spec, geometry, context, "spec "));
}

Structure::Structure(BuiltStructure built) : built_(std::move(built)) {}

Hit Structure::intersect(const Ray& ray) const {
  return std::visit([&](const auto& s) { return s.intersect(ray); }, built_.structure);
}

bool Structure::occluded(const Ray& ray) const {
  return std::visit([&](const auto& s) { return s.occluded(ray); }, built_.structure);
}

void Structure::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
  intersect_batch(built_.structure, rays, hits);
}

void Structure::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const {
  occluded_batch(built_.structure, rays, occluded);
}

bool Structure::exact() const {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::exactness == Exactness::exact; }, built_.structure);
}

bool Structure::updatable() const {
  return is_updatable(built_.structure);
}

AccelStats Structure::stats() const {
  return structure_stats(built_.structure);
}

void Structure::remove(ObjectId id) {
  remove_object(built_.structure, id);
}

void Structure::insert(const Scene& scene, ObjectId id) {
  insert_object(built_.structure, scene, id);
}

void Structure::move(ObjectId id, const Transform& t) {
  move_object(built_.structure, id, t);
}

void Structure::commit() {
  commit_objects(built_.structure);
}

}  // namespace vf
