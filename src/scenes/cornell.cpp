// "cornell": a Cornell-like room (the default demo scene). Room [-1,1] x [0,2] x [-1,1], open towards
// +z where the camera stands; red left wall, green right wall; a square light set flush into the
// ceiling (the ceiling is a frame around it, so no T-junctions and no coplanar overlap) plus a point
// light just below it. Inside: a tall box, a short box and a tessellated sphere on the floor, which
// give the contact shadows and creases that make ambient occlusion worth looking at.

#include "generators.hpp"
#include "mesh_builders.hpp"

namespace vf::scenes {
namespace {

constexpr float kLightHalf = 0.25f;  // the ceiling light is 0.5 x 0.5

// Horizontal square of half-width h at height y, counter-clockwise seen from below (-y).
Quad square_facing_down(float h, float y) {
  return {Vec3f{-h, y, -h}, Vec3f{h, y, -h}, Vec3f{h, y, h}, Vec3f{-h, y, h}};
}

}  // namespace

Scene make_cornell_scene(std::size_t sphere_triangles) {
  Scene scene;
  const std::uint32_t white = add_material(scene, make_material("white", {0.73f, 0.73f, 0.73f}));
  const std::uint32_t red = add_material(scene, make_material("red", {0.65f, 0.05f, 0.05f}));
  const std::uint32_t green = add_material(scene, make_material("green", {0.12f, 0.45f, 0.15f}));
  const std::uint32_t light = add_material(scene, make_material("light", Vec3f{0.78f}, {17.0f, 12.0f, 4.0f}));

  TriangleMesh room;
  room.name = "room";
  const Vec3f l0{-1, 0, -1}, l1{-1, 0, 1}, r0{1, 0, -1}, r1{1, 0, 1};  // floor corners
  const Vec3f up{0, 2, 0};
  add_quad(room, {l0, l1, r1, r0}, white);                        // floor, facing +y
  add_quad(room, {l0, r0, r0 + up, l0 + up}, white);              // back wall, facing +z
  add_quad(room, {l1, l0, l0 + up, l1 + up}, red);                // left wall, facing +x
  add_quad(room, {r0, r1, r1 + up, r0 + up}, green);              // right wall, facing -x
  add_quad_frame(room, square_facing_down(kLightHalf, 2.0f), square_facing_down(1.0f, 2.0f), white);  // ceiling
  add_quad(room, square_facing_down(kLightHalf, 2.0f), light);   // the light fills the ceiling's hole

  room.occluder = MeshOccluder::exact;  // the receiver around the objects
  scene.meshes.push_back(std::move(room));
  scene.meshes.push_back(make_box_mesh("cube", {Vec3f{-0.5f}, Vec3f{0.5f}}));
  scene.meshes.push_back(make_box_mesh("tall box", {Vec3f{-0.3f, 0.0f, -0.3f}, Vec3f{0.3f, 1.2f, 0.3f}}));
  scene.meshes.push_back(make_sphere_mesh("sphere", {0.0f, 0.0f, 0.0f}, 1.0f, sphere_triangles));

  scene.add_instance(Instance{});
  Instance short_box;
  short_box.mesh = 1;
  short_box.transform.scale = 0.6f;
  short_box.transform.rotation = Mat3::rotation({0, 1, 0}, -17.0f);
  short_box.transform.translation = {0.4f, 0.3f, 0.3f};
  short_box.material = white;
  scene.add_instance(short_box);
  Instance tall_box;
  tall_box.mesh = 2;
  tall_box.transform.rotation = Mat3::rotation({0, 1, 0}, 17.0f);
  tall_box.transform.translation = {-0.4f, 0.0f, -0.4f};
  tall_box.material = white;
  scene.add_instance(tall_box);
  Instance sphere;
  sphere.mesh = 3;
  sphere.transform.scale = 0.28f;
  sphere.transform.translation = {-0.45f, 0.28f, 0.5f};
  sphere.material = white;
  scene.add_instance(sphere);

  Camera camera;
  camera.position = {0.0f, 1.0f, 3.9f};
  camera.look_at = {0.0f, 1.0f, 0.0f};
  camera.fov_degrees = 38.0f;
  scene.camera = camera;
  // Radiant intensity of the light quad along its normal: radiance x area.
  scene.point_lights.push_back(PointLight{{0.0f, 1.98f, 0.0f}, Vec3f{17.0f, 12.0f, 4.0f} * (4.0f * kLightHalf * kLightHalf), true});
  return scene;
}

}  // namespace vf::scenes
