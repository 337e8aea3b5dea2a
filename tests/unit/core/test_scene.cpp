#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "visfield/core/error.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {
namespace {

Scene two_meshes() {
  Scene scene;
  TriangleMesh tri;
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.triangles = {{0, 1, 2}};
  scene.meshes = {tri, tri};
  return scene;
}

TEST(Scene, ObjectIdsAreStableAcrossEdits) {
  Scene scene = two_meshes();
  const ObjectId a = scene.add_instance(0), b = scene.add_instance(1), c = scene.add_instance(0);
  EXPECT_EQ(a, 0u);
  EXPECT_EQ(b, 1u);
  EXPECT_EQ(c, 2u);
  scene.remove_instance(b);
  EXPECT_EQ(scene.instances().size(), 2u);
  EXPECT_EQ(scene.instance(c).id, c);  // not renumbered
  EXPECT_EQ(scene.instance(c).mesh, 0u);
  EXPECT_EQ(scene.find_instance(b), nullptr);
  const ObjectId d = scene.add_instance(1);
  EXPECT_EQ(d, 3u);  // never reused
  Transform moved;
  moved.translation = {0, 0, 5};
  scene.set_transform(a, moved);
  EXPECT_EQ(scene.instance(a).transform.translation.z, 5.0f);
  // The objects stay in id order, and flatten tags triangles with the ids.
  const TriangleSet set = flatten(scene);
  ASSERT_EQ(set.size(), 3u);
  EXPECT_EQ(set.instance, (std::vector<ObjectId>{a, c, d}));
  EXPECT_FLOAT_EQ(set.triangles[0][0].z, 5.0f);
}

TEST(Scene, BadEditsAreRefused) {
  Scene scene = two_meshes();
  EXPECT_THROW(scene.add_instance(2), Error);  // no such mesh
  Instance bad_material{kInvalidId, 0, Transform{}, 7};
  EXPECT_THROW(scene.add_instance(bad_material), Error);
  Transform flat;
  flat.scale = 0.0f;
  EXPECT_THROW(scene.add_instance(0, flat), Error);
  Transform nan;
  nan.translation.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(scene.add_instance(0, nan), Error);
  const ObjectId a = scene.add_instance(0);
  EXPECT_THROW(scene.set_transform(a, flat), Error);
  EXPECT_THROW(scene.remove_instance(a + 1), Error);
  EXPECT_THROW(scene.instance(a + 1), Error);
  EXPECT_EQ(scene.instances().size(), 1u);
}

TEST(Scene, MaterialLookupFollowsTheObjectId) {
  Scene scene = two_meshes();
  Material red;
  red.diffuse = {1, 0, 0};
  scene.materials.push_back(red);
  const ObjectId plain = scene.add_instance(0);
  const ObjectId painted = scene.add_instance(Instance{kInvalidId, 1, Transform{}, 1});
  scene.remove_instance(plain);
  EXPECT_EQ(scene.material_of(painted, 0).diffuse.x, 1.0f);
}

TEST(Scene, DefaultCameraIsTheFramedThreeQuarterView) {
  Scene scene = two_meshes();
  scene.add_instance(0);
  scene.add_instance(1, Transform{Mat3{}, Vec3f{3.0f, 0.5f, -1.0f}, 2.0f});
  const Camera c = scene.camera_or_default(64, 48);
  EXPECT_EQ(c.width, 64);
  EXPECT_EQ(c.height, 48);
  const Camera framed = framed_view(scene, Vec3f{0.0f, 1.0f, 0.0f}, kDefaultAzimuth, kDefaultElevation, 45.0f, 64, 48);
  EXPECT_EQ(c.position, framed.position);
  EXPECT_EQ(c.look_at, framed.look_at);
  // Every vertex projects within 90% of the half-width and half-height, and one reaches it: framed.
  const Vec3f forward = normalize(c.look_at - c.position);
  const Vec3f right = normalize(cross(forward, c.up)), up = cross(right, forward);
  const float tan_y = std::tan(0.5f * c.fov_degrees * 3.14159265f / 180.0f), tan_x = tan_y * 64.0f / 48.0f;
  float widest = 0.0f;
  for (const Instance& inst : scene.instances())
    for (const Vec3f& p : scene.meshes[inst.mesh].positions) {
      const Vec3f d = inst.transform.apply_point(p) - c.position;
      const float depth = dot(d, forward);
      ASSERT_GT(depth, 0.0f);
      const float x = std::fabs(dot(d, right)) / (depth * tan_x), y = std::fabs(dot(d, up)) / (depth * tan_y);
      EXPECT_LE(x, 0.9f + 1e-4f);
      EXPECT_LE(y, 0.9f + 1e-4f);
      widest = std::max({widest, x, y});
    }
  EXPECT_GT(widest, 0.85f);
  // The view is from the front-right and above, as the angles say.
  const Vec3f from = c.position - c.look_at;
  EXPECT_GT(from.z, 0.0f);
  EXPECT_GT(from.x, 0.0f);
  EXPECT_GT(from.y, 0.0f);
  // A scene's own camera wins.
  scene.camera = Camera{};
  EXPECT_EQ(scene.camera_or_default(0, 0).position, Camera{}.position);
}

}  // namespace
}  // namespace vf
