#include "visfield/core/scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "visfield/core/error.hpp"

namespace vf {
namespace {

void check_transform(const Transform& t, const std::string& what) {
  if (!t.is_valid())
    throw Error(what + ": the transform must be a rotation (orthonormal, determinant +1), a finite translation and a finite scale > 0");
}

}  // namespace

ObjectId Scene::add_instance(Instance instance) {
  if (instance.mesh >= meshes.size())
    throw Error("scene: instance of mesh " + std::to_string(instance.mesh) + ", but the scene has " +
                std::to_string(meshes.size()) + " meshes");
  if (instance.material && *instance.material >= materials.size())
    throw Error("scene: instance material " + std::to_string(*instance.material) + " is out of range (" +
                std::to_string(materials.size()) + " materials)");
  check_transform(instance.transform, "scene: instance of mesh " + std::to_string(instance.mesh));
  if (next_id_ == kInvalidId) throw Error("scene: no object ids left");
  instance.id = next_id_++;
  instances_.push_back(instance);
  return instance.id;
}

ObjectId Scene::add_instance(std::uint32_t mesh, const Transform& transform) {
  return add_instance(Instance{kInvalidId, mesh, transform, std::nullopt});
}

const Instance* Scene::find_instance(ObjectId id) const {
  const auto it = std::lower_bound(instances_.begin(), instances_.end(), id,
                                   [](const Instance& a, ObjectId b) { return a.id < b; });
  return it != instances_.end() && it->id == id ? &*it : nullptr;
}

const Instance& Scene::instance(ObjectId id) const {
  const Instance* found = find_instance(id);
  if (!found) throw Error("scene: no object has id " + std::to_string(id));
  return *found;
}

void Scene::remove_instance(ObjectId id) {
  const Instance& found = instance(id);
  instances_.erase(instances_.begin() + (&found - instances_.data()));
}

void Scene::set_transform(ObjectId id, const Transform& transform) {
  const Instance& found = instance(id);
  check_transform(transform, "scene: object " + std::to_string(id));
  instances_[static_cast<std::size_t>(&found - instances_.data())].transform = transform;
}

namespace {
// Each mesh's bounds, read once however many objects share it (1,024 copies of a 35K-vertex mesh
// read 36M vertices when each object read its mesh's).
std::vector<Bounds3f> bounds_of_meshes(const std::vector<TriangleMesh>& meshes) {
  std::vector<Bounds3f> bounds;
  bounds.reserve(meshes.size());
  for (const TriangleMesh& mesh : meshes) bounds.push_back(mesh.bounds());
  return bounds;
}
}  // namespace

Bounds3f Scene::bounds() const {
  const std::vector<Bounds3f> mesh_bounds = bounds_of_meshes(meshes);
  Bounds3f b;
  for (const Instance& inst : instances_) b.extend(inst.transform.apply_bounds(mesh_bounds[inst.mesh]));
  return b;
}

void Scene::check_coordinate_range(const std::string& what) const {
  const std::vector<Bounds3f> mesh_bounds = bounds_of_meshes(meshes);
  for (const Instance& inst : instances_) {
    const Bounds3f world = inst.transform.apply_bounds(mesh_bounds[inst.mesh]);
    if (world.empty()) continue;
    const float reach = std::fmax(max_component(abs(world.lo)), max_component(abs(world.hi)));
    if (!(reach <= kMaxCoordinate)) {
      std::ostringstream msg;
      msg << what << ": object " << inst.id << " (mesh " << inst.mesh
          << (meshes[inst.mesh].name.empty() ? "" : " \"" + meshes[inst.mesh].name + "\"") << ") reaches coordinate "
          << reach << " in world space, beyond the ±" << kMaxCoordinate << " visfield supports";
      throw Error(msg.str());
    }
  }
}

std::size_t Scene::instanced_triangle_count() const {
  std::size_t n = 0;
  for (const Instance& inst : instances_) n += meshes[inst.mesh].triangles.size();
  return n;
}

Camera framing_camera(const Bounds3f& target, const Vec3f& view_direction, float fov_degrees) {
  Camera camera;
  camera.fov_degrees = fov_degrees;
  const float radius = 0.5f * length(target.extent());
  const float half_fov = 0.5f * fov_degrees * std::numbers::pi_v<float> / 180.0f;
  camera.look_at = target.center();
  camera.position = camera.look_at + normalize(view_direction) * (radius / std::sin(half_fov) * 1.05f);
  return camera;
}

Camera Scene::camera_or_default(int width, int height) const {
  Camera c = camera ? *camera : framing_camera(bounds(), Vec3f{0.35f, 0.3f, 1.0f}, Camera{}.fov_degrees);
  if (width > 0) c.width = width;
  if (height > 0) c.height = height;
  return c;
}

const Material& Scene::material_of(ObjectId id, std::uint32_t prim) const {
  const Instance& inst = instance(id);
  if (inst.material) return materials[*inst.material];
  const TriangleMesh& mesh = meshes[inst.mesh];
  if (mesh.material_ids.empty()) return materials[0];
  return materials[mesh.material_ids[prim == kInvalidId ? 0 : prim]];
}

Scene scene_from_mesh(TriangleMesh mesh) {
  Scene scene;
  scene.name = mesh.name;
  scene.meshes.push_back(std::move(mesh));
  scene.add_instance(0);
  return scene;
}

}  // namespace vf
