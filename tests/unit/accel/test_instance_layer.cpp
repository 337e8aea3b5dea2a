#include <cstdint>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "support/same_hit.hpp"
#include "visfield/accel/instance_layer.hpp"

namespace vf {
namespace {

MeshStructure build_bvh(const TriangleSet& set) { return Bvh::build(set); }

TEST(InstanceLayer, OneIdentityObjectAnswersAsTheFlattenedBvh) {
  const Scene scene = test::scene_from_triangles(test::random_soup(3, 2000, 0.01f, 0.1f));
  const InstanceLayer layer = InstanceLayer::build(scene, build_bvh);
  const TriangleSet set = flatten(scene);
  const Bvh flat = Bvh::build(set);
  for (const Ray& ray : test::random_rays(set, 4, 2000)) {
    ASSERT_TRUE(test::same_bits(layer.intersect(ray), flat.intersect(ray)));
    ASSERT_EQ(layer.occluded(ray), flat.occluded(ray));
  }
}

TEST(InstanceLayer, MovedObjectsAreHitWhereTheyStandWithWorldNormals) {
  // A unit square in the z = 0 plane, placed twice: turned to face +x at x = 10 (scaled by 2), and
  // moved to z = -3.
  Scene scene = test::scene_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{1, 1, 0}},
                                            {Vec3f{0, 0, 0}, Vec3f{1, 1, 0}, Vec3f{0, 1, 0}}});
  scene.remove_instance(0);
  Transform facing_x;
  facing_x.rotation = Mat3::rotation({0, 1, 0}, 90.0f);
  facing_x.translation = {10, 0, 0};
  facing_x.scale = 2.0f;
  const ObjectId turned = scene.add_instance(0, facing_x);
  Transform below;
  below.translation = {0, 0, -3};
  const ObjectId lowered = scene.add_instance(0, below);
  const InstanceLayer layer = InstanceLayer::build(scene, build_bvh);

  const Hit side = layer.intersect(Ray{{0, 0.6f, -0.5f}, {1, 0, 0}});
  ASSERT_TRUE(side);
  EXPECT_EQ(side.instance, turned);
  EXPECT_NEAR(side.t, 10.0f, 1e-5f);
  ASSERT_TRUE(side.has_normal);
  EXPECT_NEAR(std::fabs(normalize(side.normal).x), 1.0f, 1e-5f);
  EXPECT_NEAR(length(side.normal), 4.0f, 1e-4f);  // |cross| of edges scaled by 2: 2^2 times the object's 1

  const Hit down = layer.intersect(Ray{{0.25f, 0.5f, 1}, {0, 0, -1}});
  ASSERT_TRUE(down);
  EXPECT_EQ(down.instance, lowered);
  EXPECT_NEAR(down.t, 4.0f, 1e-6f);
  EXPECT_FALSE(layer.occluded(Ray{{0.25f, 0.5f, 1}, {0, 0, -1}, 0.0f, 3.9f}));
  EXPECT_TRUE(layer.occluded(Ray{{0.25f, 0.5f, 1}, {0, 0, -1}, 0.0f, 4.1f}));
  EXPECT_FALSE(layer.intersect(Ray{{0.25f, 0.5f, 1}, {0, 0, 1}}));
}

TEST(InstanceLayer, MeshStructuresAreSharedByTheirObjects) {
  Scene scene = test::scene_from_triangles(test::random_soup(5, 5000, 0.01f, 0.1f));
  const std::size_t one = InstanceLayer::build(scene, build_bvh).stats().memory_bytes;
  for (int i = 1; i < 100; ++i) {
    Transform t;
    t.translation = {static_cast<float>(i), 0, 0};
    scene.add_instance(0, t);
  }
  const AccelStats hundred = InstanceLayer::build(scene, build_bvh).stats();
  // 99 more objects cost their top-level entries, not 99 more copies of the mesh's BVH.
  EXPECT_LT(hundred.memory_bytes, one + 100 * 512);
  EXPECT_GT(hundred.memory_bytes, one);
  EXPECT_EQ(hundred.reference_count, InstanceLayer::build(scene, build_bvh).stats().reference_count);
}

TEST(InstanceLayer, StreamedOcclusionAnswersAsOneRayAtATime) {
  // Overlapping turned and scaled copies of a mesh under a Bvh (its walks stepped in the stream), one
  // under a grid and one under a one-node Bvh (both answered as their step comes), and a zero-area mesh.
  Scene scene = test::scene_from_triangles(test::random_soup(6, 3000, 0.01f, 0.1f));
  scene.meshes.push_back(test::scene_from_triangles(test::random_soup(7, 400, 0.02f, 0.2f)).meshes[0]);
  scene.meshes.push_back(test::scene_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{2, 0, 0}}}).meshes[0]);
  scene.meshes.push_back(test::scene_from_triangles(test::random_soup(10, 12, 0.2f, 0.5f)).meshes[0]);
  Rng place(8);
  for (int i = 0; i < 80; ++i) {
    Transform t;
    t.rotation = Mat3::rotation(Vec3f{place.uniform(), place.uniform(), place.uniform()} + Vec3f{0.1f}, 360.0f * place.uniform());
    t.scale = 0.5f + place.uniform();
    t.translation = Vec3f{place.uniform(), place.uniform(), place.uniform()} * 3.0f;
    scene.add_instance(static_cast<std::uint32_t>(i % 4), t);
  }
  const InstanceLayer layer = InstanceLayer::build(scene, [](const TriangleSet& set) -> MeshStructure {
    if (set.size() > 1000 || set.size() < 20) return Bvh::build(set);
    return UniformGrid::build(set);
  });
  const TriangleSet world = flatten(scene);
  std::vector<Ray> rays = test::random_rays(world, 9, 2001);
  for (std::size_t i = 0; i < rays.size(); i += 5) rays[i].tmax = 0.05f;  // short ones end early
  std::size_t hits = 0;
  for (const std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{5}, rays.size()}) {
    std::vector<std::uint8_t> block(count, 7), batch(count, 7);
    const std::span<const Ray> some(rays.data(), count);
    occluded_block(layer, some, block);
    occluded_batch(layer, some, batch);
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint8_t expected = layer.occluded(rays[i]) ? 1 : 0;
      ASSERT_EQ(block[i], expected) << count << " rays, ray " << i;
      ASSERT_EQ(batch[i], expected) << count << " rays, ray " << i;
      if (count == rays.size()) hits += expected;
    }
  }
  EXPECT_GT(hits, 100u);
  EXPECT_LT(hits, rays.size() - 100u);
}

TEST(InstanceLayer, EmptyScenesAndEmptyMeshesNeverHit) {
  Scene scene = test::scene_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{2, 0, 0}}});  // zero area
  const InstanceLayer layer = InstanceLayer::build(scene, build_bvh);
  EXPECT_FALSE(layer.intersect(Ray{{0.5f, -1, 0}, {0, 1, 0}}));
  EXPECT_FALSE(layer.occluded(Ray{{0.5f, -1, 0}, {0, 1, 0}}));
  scene.remove_instance(0);
  const InstanceLayer empty = InstanceLayer::build(scene, build_bvh);
  EXPECT_FALSE(empty.intersect(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_EQ(empty.object_count(), 0u);
}

}  // namespace
}  // namespace vf
