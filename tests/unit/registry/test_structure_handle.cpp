// vf::Structure answers as the concrete structure it holds, bit for bit, one ray or a batch at a time.

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "support/same_hit.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/registry/structure.hpp"

namespace vf {
namespace {

const Scene& soup_scene() {
  static const Scene scene = test::scene_from_triangles(test::random_soup(37, 800, 0.05f, 0.12f));
  return scene;
}

std::vector<Ray> soup_rays(std::size_t n) {
  return test::random_rays(test::set_from_triangles(test::random_soup(37, 800, 0.05f, 0.12f)), 91, n);
}

class StructureHandle : public ::testing::TestWithParam<const char*> {};

TEST_P(StructureHandle, AnswersAsTheConcreteStructureOneRayAndABatchAtATime) {
  const Structure handle = Structure::build(soup_scene(), GetParam());
  const std::vector<Ray> rays = soup_rays(3000);
  std::vector<Hit> expected(rays.size()), batch(rays.size());
  std::vector<std::uint8_t> expected_blocked(rays.size()), blocked(rays.size());
  std::visit(
      [&](const auto& s) {
        intersect_batch(s, std::span<const Ray>(rays), std::span<Hit>(expected));
        occluded_batch(s, std::span<const Ray>(rays), std::span<std::uint8_t>(expected_blocked));
      },
      handle.variant());
  handle.intersect(rays, batch);
  handle.occluded(rays, blocked);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(test::same_bits(expected[i], batch[i])) << GetParam() << " ray " << i;
    ASSERT_TRUE(test::same_bits(expected[i], handle.intersect(rays[i]))) << GetParam() << " ray " << i;
    ASSERT_EQ(expected_blocked[i], blocked[i]) << GetParam() << " ray " << i;
    ASSERT_EQ(expected_blocked[i] != 0, handle.occluded(rays[i])) << GetParam() << " ray " << i;
    hits += expected[i] ? 1 : 0;
  }
  EXPECT_GT(hits, rays.size() / 20) << "the rays must hit something for the comparison to mean anything";
  EXPECT_TRUE(handle.spec().starts_with(std::string(GetParam()).substr(0, 3))) << handle.spec();
  EXPECT_GT(handle.stats().memory_bytes, 0u);
}

INSTANTIATE_TEST_SUITE_P(Specs, StructureHandle,
                         ::testing::Values("bvh", "bvh:levels=2", "kdtree", "grid", "median-bsp", "brute", "beam:dirs=33,n=16",
                                           "field:positions=290,directions=16"));

TEST(StructureHandleTypes, TheConcreteTypeIsReachableAndTheFlagsAreTheStructures) {
  const Structure bvh = Structure::build(soup_scene(), "bvh");
  EXPECT_NE(bvh.get<Bvh>(), nullptr);
  EXPECT_EQ(bvh.get<KdTree>(), nullptr);
  EXPECT_TRUE(bvh.exact());
  EXPECT_FALSE(bvh.updatable());
  const Structure field = Structure::build(soup_scene(), "field:positions=290,directions=16");
  EXPECT_FALSE(field.exact());
  EXPECT_NE(field.get<field::FieldScene>(), nullptr);
}

TEST(StructureHandleEdits, AMovedObjectAnswersAsAFreshBuild) {
  Scene scene = test::scattered_copies({test::mesh_from_triangles(test::random_soup(5, 200, 0.05f, 0.1f))}, 6, 4.0f, 17);
  Structure handle = Structure::build(scene, "bvh:levels=2");
  ASSERT_TRUE(handle.updatable());
  const ObjectId id = scene.instances()[2].id;
  Transform t = scene.instances()[2].transform;
  t.translation = t.translation + Vec3f{0.5f, -0.25f, 0.75f};
  handle.move(id, t);
  handle.commit();
  scene.set_transform(id, t);
  const Structure fresh = Structure::build(scene, "bvh:levels=2");
  std::vector<Ray> rays = test::random_rays(test::set_from_triangles(test::random_soup(5, 200, 0.05f, 0.1f)), 3, 2000);
  for (Ray& r : rays) r.org = r.org * 4.0f;
  for (const Ray& r : rays) ASSERT_TRUE(test::same_bits(fresh.intersect(r), handle.intersect(r)));
}

TEST(StructureHandleErrors, BadSpecsEmptyScenesAndUneditableStructuresAreRefused) {
  EXPECT_THROW(Structure::build(soup_scene(), "nonsense"), Error);
  EXPECT_THROW(Structure::build(Scene{}, "bvh"), Error);
  Structure bvh = Structure::build(soup_scene(), "bvh");
  EXPECT_THROW(bvh.remove(0), Error);
  const std::vector<Ray> rays(3);
  std::vector<Hit> hits(2);
  EXPECT_THROW(bvh.intersect(rays, hits), Error);
}

}  // namespace
}  // namespace vf
