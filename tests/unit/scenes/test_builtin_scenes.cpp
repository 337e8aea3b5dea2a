#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "visfield/accel/brute_force.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

const TriangleMesh* find_mesh(const Scene& scene, const std::string& name) {
  for (const TriangleMesh& m : scene.meshes)
    if (m.name == name) return &m;
  return nullptr;
}

// Every directed edge exactly once and its reverse exactly once: closed, manifold, consistently wound.
void expect_closed_and_oriented(const TriangleMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const TriangleIndices& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  std::size_t bad = 0;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++bad;
  }
  EXPECT_EQ(bad, 0u) << mesh.name;
}

// Volume enclosed by a closed mesh (divergence theorem); positive when the triangles face outwards.
double signed_volume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const TriangleIndices& t : mesh.triangles) {
    const Vec3f a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    volume += static_cast<double>(dot(a, cross(b, c))) / 6.0;
  }
  return volume;
}

void expect_well_formed(const Scene& scene) {
  ASSERT_TRUE(scene.camera.has_value()) << scene.name;
  for (const TriangleMesh& mesh : scene.meshes) {
    EXPECT_NO_THROW(validate_mesh(mesh, mesh.name));
    EXPECT_EQ(mesh.count_degenerate(), 0u) << mesh.name;
    for (std::uint32_t id : mesh.material_ids) EXPECT_LT(id, scene.materials.size()) << mesh.name;
  }
  for (const Instance& inst : scene.instances()) {
    EXPECT_LT(inst.mesh, scene.meshes.size());
    if (inst.material) {
      EXPECT_LT(*inst.material, scene.materials.size());
    }
  }
  // The camera looks into the scene: its central ray hits geometry.
  const Camera& cam = *scene.camera;
  EXPECT_GT(length(cam.look_at - cam.position), 0.0f);
  EXPECT_TRUE(scene.bounds().contains(cam.look_at)) << scene.name;
  const TriangleSet set = flatten(scene);
  EXPECT_EQ(set.degenerate_count, 0u);
  EXPECT_TRUE(BruteForce::build(set).intersect(Ray{cam.position, normalize(cam.look_at - cam.position)})) << scene.name;
}

TEST(BuiltinScenes, EveryNameBuildsAWellFormedSceneWithACamera) {
  for (const std::string& name : builtin_scene_names()) {
    SCOPED_TRACE(name);
    EXPECT_FALSE(builtin_scene_description(name).empty());
    const Scene scene = make_builtin_scene(name, {.seed = 3, .size = name == "soup" ? 20000u : 0u});
    expect_well_formed(scene);
    EXPECT_EQ(scene.name.rfind("builtin:" + name + ":", 0), 0u);
  }
}

TEST(BuiltinScenes, SoupHasExactlySizeTrianglesInsideTheUnitCube) {
  const Scene scene = make_builtin_scene("soup", {.seed = 5, .size = 1234});
  EXPECT_EQ(scene.instanced_triangle_count(), 1234u);
  const Bounds3f b = scene.bounds();
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GE(b.lo[axis], 0.0f);
    EXPECT_LE(b.hi[axis], 1.0f);
    EXPECT_LT(b.lo[axis], 0.05f);  // uniform: the triangles spread over the whole cube
    EXPECT_GT(b.hi[axis], 0.95f);
  }
  EXPECT_EQ(make_builtin_scene("soup").instanced_triangle_count(), 100000u);
  EXPECT_FALSE(scene.point_lights.empty());
}

TEST(BuiltinScenes, SoupIsDeterministicPerSeed) {
  const Scene a = make_builtin_scene("soup", {.seed = 7, .size = 5000});
  const Scene b = make_builtin_scene("soup", {.seed = 7, .size = 5000});
  const Scene c = make_builtin_scene("soup", {.seed = 8, .size = 5000});
  EXPECT_EQ(a.meshes[0].positions, b.meshes[0].positions);
  EXPECT_EQ(a.meshes[0].triangles, b.meshes[0].triangles);
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.meshes[0].positions.size(); ++i) differing += a.meshes[0].positions[i] != c.meshes[0].positions[i];
  EXPECT_EQ(differing, a.meshes[0].positions.size());
}

TEST(BuiltinScenes, SphereIsClosedOutwardRoundAndHasExactlySizeTriangles) {
  for (std::size_t size : {8u, 10u, 100u, 2000u, 20001u}) {
    SCOPED_TRACE(size);
    const Scene scene = make_builtin_scene("sphere", {.size = size});
    const TriangleMesh* sphere = find_mesh(scene, "sphere");
    ASSERT_NE(sphere, nullptr);
    EXPECT_EQ(sphere->triangles.size(), size / 2 * 2);  // closed meshes have an even triangle count
    EXPECT_EQ(scene.instanced_triangle_count(), size / 2 * 2 + 2);  // + the ground quad
    expect_closed_and_oriented(*sphere);
    for (const Vec3f& p : sphere->positions) EXPECT_NEAR(length(p - Vec3f{0, 1, 0}), 1.0f, 1e-5f);
    EXPECT_GT(signed_volume(*sphere), 0.0);
  }
  const Scene default_scene = make_builtin_scene("sphere");
  const TriangleMesh* fine = find_mesh(default_scene, "sphere");
  EXPECT_EQ(fine->triangles.size(), 20000u);
  EXPECT_NEAR(signed_volume(*fine), 4.0 / 3.0 * M_PI, 0.01);  // a fine tessellation of the unit sphere
}

TEST(BuiltinScenes, StadiumIsADenseClosedKnotInAHundredTimesLargerArena) {
  const Scene scene = make_builtin_scene("stadium", {.size = 30000});
  const TriangleMesh* knot = find_mesh(scene, "knot");
  ASSERT_NE(knot, nullptr);
  EXPECT_EQ(knot->triangles.size(), 30000u);
  expect_closed_and_oriented(*knot);
  EXPECT_GT(signed_volume(*knot), 0.0);
  Bounds3f knot_bounds;
  for (const Instance& inst : scene.instances())
    if (scene.meshes[inst.mesh].name == "knot") knot_bounds.extend(inst.transform.apply_bounds(knot->bounds()));
  const float ratio = max_component(scene.bounds().extent()) / max_component(knot_bounds.extent());
  EXPECT_GT(ratio, 50.0f);
  EXPECT_LT(ratio, 200.0f);
  EXPECT_LT(scene.instanced_triangle_count() - knot->triangles.size(), 50u);  // the arena is sparse
  EXPECT_TRUE(knot_bounds.contains(scene.camera->look_at));
  EXPECT_EQ(find_mesh(make_builtin_scene("stadium", {.size = 18}), "knot")->triangles.size(), 18u);
}

TEST(BuiltinScenes, BoxesAreInstancesOfOneClosedCube) {
  for (std::size_t count : {1u, 5u, 64u, 100u}) {
    SCOPED_TRACE(count);
    const Scene scene = make_builtin_scene("boxes", {.seed = 2, .size = count});
    const TriangleMesh* cube = find_mesh(scene, "cube");
    ASSERT_NE(cube, nullptr);
    EXPECT_EQ(cube->triangles.size(), 12u);
    expect_closed_and_oriented(*cube);
    EXPECT_NEAR(signed_volume(*cube), 1.0, 1e-6);
    std::size_t boxes = 0;
    for (const Instance& inst : scene.instances()) {
      if (&scene.meshes[inst.mesh] != cube) continue;
      ++boxes;
      EXPECT_GE(inst.transform.apply_bounds(cube->bounds()).lo.y, -1e-6f);  // resting on or above the ground
    }
    EXPECT_EQ(boxes, count);
    EXPECT_EQ(scene.instanced_triangle_count(), 12 * count + 2);
  }
  const Scene a = make_builtin_scene("boxes", {.seed = 2}), b = make_builtin_scene("boxes", {.seed = 2});
  const Scene c = make_builtin_scene("boxes", {.seed = 3});
  EXPECT_EQ(a.instances().back().transform.rotation.rows, b.instances().back().transform.rotation.rows);
  EXPECT_NE(a.instances().back().transform.rotation.rows, c.instances().back().transform.rotation.rows);
}

TEST(BuiltinScenes, BoxesDoNotOverlap) {
  const Scene scene = make_builtin_scene("boxes", {.seed = 9, .size = 30});
  const TriangleMesh* cube = find_mesh(scene, "cube");
  std::vector<Bounds3f> boxes;
  for (const Instance& inst : scene.instances())
    if (&scene.meshes[inst.mesh] == cube) boxes.push_back(inst.transform.apply_bounds(cube->bounds()));
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      // Boxes in one layer keep a gap; boxes in different layers touch at most along a face.
      const Bounds3f& p = boxes[i];
      const Bounds3f& q = boxes[j];
      const bool apart = p.hi.x < q.lo.x || q.hi.x < p.lo.x || p.hi.z < q.lo.z || q.hi.z < p.lo.z ||
                         p.hi.y <= q.lo.y + 1e-5f || q.hi.y <= p.lo.y + 1e-5f;
      EXPECT_TRUE(apart) << i << " " << j;
    }
}

TEST(BuiltinScenes, CornellHasLightsAndTheRequestedSphere) {
  const Scene scene = make_builtin_scene("cornell", {.size = 500});
  const TriangleMesh* sphere = find_mesh(scene, "sphere");
  ASSERT_NE(sphere, nullptr);
  EXPECT_EQ(sphere->triangles.size(), 500u);
  EXPECT_EQ(find_mesh(make_builtin_scene("cornell"), "sphere")->triangles.size(), 4000u);
  bool emissive = false;
  for (const Material& m : scene.materials) emissive |= max_component(m.emission) > 0.0f;
  EXPECT_TRUE(emissive);
  EXPECT_EQ(scene.point_lights.size() + scene.sphere_lights.size(), 1u);
  const Bounds3f b = scene.bounds();
  EXPECT_EQ(b.lo, (Vec3f{-1, 0, -1}));
  EXPECT_EQ(b.hi, (Vec3f{1, 2, 1}));
  // The room is open towards the camera, and the camera is outside it.
  EXPECT_GT(scene.camera->position.z, 1.0f);
  expect_closed_and_oriented(*sphere);
}

TEST(BuiltinScenes, SizesOutOfRangeAreRefused) {
  EXPECT_THROW(make_builtin_scene("soup", {.size = kMaxBuiltinTriangles + 1}), Error);
  EXPECT_THROW(make_builtin_scene("boxes", {.size = kMaxBuiltinTriangles / 12 + 1}), Error);
  EXPECT_THROW(make_builtin_scene("sphere", {.size = 6}), Error);
  EXPECT_THROW(make_builtin_scene("stadium", {.size = 17}), Error);
  EXPECT_THROW(make_builtin_scene("cornell", {.size = 7}), Error);
  try {
    make_builtin_scene("sphere", {.size = 3});
    FAIL() << "expected vf::Error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("builtin:sphere"), std::string::npos) << msg;
    EXPECT_NE(msg.find("size 3"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos);
  }
}

TEST(BuiltinScenes, UnknownNameListsTheValidOnes) {
  try {
    make_builtin_scene("teapot");
    FAIL() << "expected vf::Error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const std::string& name : builtin_scene_names()) EXPECT_NE(msg.find(name), std::string::npos) << msg;
  }
  EXPECT_THROW(builtin_scene_description("teapot"), Error);
}

}  // namespace
}  // namespace vf
