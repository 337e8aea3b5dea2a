// "stadium": the "teapot in a stadium" problem for acceleration structures: a small, densely
// tessellated object in the middle of a huge, sparse environment. The object is a (2,3) torus knot
// (closed, with plenty of self-occlusion); the arena is a floor, a sloped stand ring and a wall ring,
// about 100x wider than the knot, open to the sky so ambient occlusion stays meaningful.

#include "generators.hpp"
#include "mesh_builders.hpp"

namespace vf::scenes {
namespace {

constexpr float kKnotScale = 0.4f;       // knot of overall width ~2.8 units
constexpr float kKnotHeight = 1.8f;      // centre height: the lowest strand floats ~0.2 above the floor
constexpr float kFieldHalf = 100.0f;     // flat field: 200 x 200
constexpr float kStandHalf = 140.0f;     // the stands rise from the field edge to this half-width...
constexpr float kStandTop = 30.0f;       // ...and this height
constexpr float kWallTop = 45.0f;        // a vertical wall ring above the stands

// Square of half-width h at height y, counter-clockwise seen from above (+y).
Quad square(float h, float y) { return {Vec3f{-h, y, -h}, Vec3f{-h, y, h}, Vec3f{h, y, h}, Vec3f{h, y, -h}}; }

}  // namespace

Scene make_stadium_scene(std::size_t knot_triangles) {
  Scene scene;
  const std::uint32_t grass = add_material(scene, make_material("field", {0.35f, 0.55f, 0.3f}));
  const std::uint32_t stands = add_material(scene, make_material("stands", Vec3f{0.6f}));
  const std::uint32_t gold = add_material(scene, make_material("knot", {0.85f, 0.65f, 0.25f}));

  TriangleMesh arena;
  arena.name = "arena";
  add_quad(arena, square(kFieldHalf, 0.0f), grass);
  add_quad_frame(arena, square(kFieldHalf, 0.0f), square(kStandHalf, kStandTop), stands);
  const Quad rim = square(kStandHalf, kStandTop);
  const Quad top = square(kStandHalf, kWallTop);
  for (int k = 0; k < 4; ++k) {
    // Walls face the field: from inside, the rim edge runs k+1 -> k.
    const int next = (k + 1) % 4;
    add_quad(arena, {rim[next], rim[k], top[k], top[next]}, stands);
  }

  Instance knot;
  knot.mesh = 1;
  knot.transform.scale = kKnotScale;
  knot.transform.translation = {0.0f, kKnotHeight, 0.0f};
  knot.material = gold;
  arena.occluder = MeshOccluder::exact;  // the receiver around the knot
  scene.meshes.push_back(std::move(arena));
  scene.meshes.push_back(make_torus_knot_mesh("knot", 2, 3, 0.5f, knot_triangles));
  scene.add_instance(Instance{});
  scene.add_instance(knot);

  const Bounds3f knot_bounds = knot.transform.apply_bounds(scene.meshes[1].bounds());
  scene.camera = framing_camera(knot_bounds, {0.3f, 0.2f, 1.0f}, 40.0f);
  scene.point_lights.push_back(PointLight{{40.0f, 120.0f, 60.0f}, Vec3f{20000.0f}});
  return scene;
}

}  // namespace vf::scenes
