// "sphere": one finely tessellated unit sphere resting on a large ground plane; the simplest smooth
// closed object, with a contact point on the ground for ambient occlusion to darken.

#include "generators.hpp"
#include "mesh_builders.hpp"

namespace vf::scenes {

Scene make_sphere_scene(std::size_t sphere_triangles) {
  Scene scene;
  const std::uint32_t ground = add_material(scene, make_material("ground", Vec3f{0.7f}));
  const std::uint32_t red = add_material(scene, make_material("sphere", {0.75f, 0.3f, 0.25f}));

  scene.meshes.push_back(make_ground_mesh("ground", 0.0f, 0.0f, 20.0f, 0.0f, ground));
  scene.meshes.push_back(make_sphere_mesh("sphere", {0.0f, 1.0f, 0.0f}, 1.0f, sphere_triangles));
  scene.add_instance(Instance{});
  Instance sphere;
  sphere.mesh = 1;
  sphere.material = red;
  scene.add_instance(sphere);

  // Frame the sphere plus the patch of ground around its contact point.
  Bounds3f view;
  view.extend(Vec3f{-1.6f, 0.0f, -1.6f});
  view.extend(Vec3f{1.6f, 2.0f, 1.6f});
  scene.camera = framing_camera(view, {0.4f, 0.45f, 1.0f}, 40.0f);
  scene.point_lights.push_back(PointLight{{3.0f, 6.0f, 4.0f}, Vec3f{40.0f}});
  return scene;
}

}  // namespace vf::scenes
