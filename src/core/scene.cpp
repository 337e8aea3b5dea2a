#include "visfield/core/scene.hpp"

#include <cmath>
#include <numbers>

namespace vf {

Bounds3f Scene::bounds() const {
  Bounds3f b;
  for (const Instance& inst : instances) b.extend(inst.transform.apply_bounds(meshes[inst.mesh].bounds()));
  return b;
}

std::size_t Scene::instanced_triangle_count() const {
  std::size_t n = 0;
  for (const Instance& inst : instances) n += meshes[inst.mesh].triangles.size();
  return n;
}

Camera Scene::camera_or_default(int width, int height) const {
  if (camera) {
    Camera c = *camera;
    if (width > 0) c.width = width;
    if (height > 0) c.height = height;
    return c;
  }
  Camera c;
  c.width = width > 0 ? width : 512;
  c.height = height > 0 ? height : 512;
  const Bounds3f b = bounds();
  const Vec3f center = b.center();
  const float radius = 0.5f * length(b.extent());
  // Distance at which the bounding sphere fills the vertical field of view, plus a margin.
  const float half_fov = 0.5f * c.fov_degrees * std::numbers::pi_v<float> / 180.0f;
  const float distance = radius / std::sin(half_fov) * 1.05f;
  c.look_at = center;
  c.position = center + normalize(Vec3f{0.35f, 0.3f, 1.0f}) * distance;
  return c;
}

Vec3f Scene::geometric_normal(std::uint32_t instance, std::uint32_t prim) const {
  const Instance& inst = instances[instance];
  const TriangleMesh& mesh = meshes[inst.mesh];
  const TriangleIndices& t = mesh.triangles[prim];
  const Vec3f a = inst.transform.apply_point(mesh.positions[t[0]]);
  const Vec3f b = inst.transform.apply_point(mesh.positions[t[1]]);
  const Vec3f c = inst.transform.apply_point(mesh.positions[t[2]]);
  return normalize(cross(b - a, c - a));
}

const Material& Scene::material_of(std::uint32_t instance, std::uint32_t prim) const {
  const Instance& inst = instances[instance];
  if (inst.material) return materials[*inst.material];
  const TriangleMesh& mesh = meshes[inst.mesh];
  return mesh.material_ids.empty() ? materials[0] : materials[mesh.material_ids[prim]];
}

Scene scene_from_mesh(TriangleMesh mesh) {
  Scene scene;
  scene.name = mesh.name;
  scene.meshes.push_back(std::move(mesh));
  scene.instances.push_back(Instance{});
  return scene;
}

}  // namespace vf
