#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "unit/accel/scalar_reference.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

using test::Triangle;

void expect_matches_scalar_loop(const TriangleSet& set, const std::vector<Ray>& rays) {
  const BruteForce bf = BruteForce::build(set);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::optional<Hit> expected = test::scalar_closest(set, rays[i]);
    const std::optional<Hit> got = bf.intersect(rays[i]);
    ASSERT_TRUE(test::same_bits(got, expected)) << "ray " << i;
    ASSERT_EQ(bf.occluded(rays[i]), test::scalar_occluded(set, rays[i])) << "ray " << i;
    hits += got.has_value();
  }
  EXPECT_GT(hits, rays.size() / 20);
}

TEST(BruteForce, BitIdenticalToScalarLoopOnRandomSoup) {
  // 1003 triangles: the last SIMD block is partly empty.
  const TriangleSet set = test::set_from_triangles(test::random_soup(11, 1003, 0.02f, 0.3f));
  std::vector<Ray> rays = test::random_rays(set, 1, 3000);
  const std::vector<Ray> surface = test::surface_origin_rays(set, 2, 1000);
  rays.insert(rays.end(), surface.begin(), surface.end());
  expect_matches_scalar_loop(set, rays);
}

TEST(BruteForce, TiesGoToTheLowestIndex) {
  // Copies of one triangle at indices 5, 9, 40: every ray through it must report prim 5.
  std::vector<Triangle> triangles = test::random_soup(12, 60, 0.1f, 0.2f);
  const Triangle repeated{Vec3f{0.1f, 0.1f, 0.5f}, Vec3f{0.9f, 0.1f, 0.5f}, Vec3f{0.5f, 0.9f, 0.5f}};
  for (std::size_t i : {5u, 9u, 40u}) triangles[i] = repeated;
  const TriangleSet set = test::set_from_triangles(triangles);
  const BruteForce bf = BruteForce::build(set);
  const std::optional<Hit> h = bf.intersect(Ray{{0.5f, 0.4f, -1.0f}, {0, 0, 1}});
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->prim, 5u);
  EXPECT_FLOAT_EQ(h->t, 1.5f);
  // Rays aimed at the repeated triangle: most hit it, each a three-way tie.
  Rng rng(3);
  std::vector<Ray> rays;
  for (int i = 0; i < 2000; ++i) {
    const Vec3f org = test::point_around(rng, set.bounds, 0.5f);
    const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
    rays.push_back(Ray{org, test::point_on(repeated, u, v) - org});
  }
  expect_matches_scalar_loop(set, rays);
}

TEST(BruteForce, ReportsPrimAndInstanceOfInstancedMeshes) {
  const Scene scene = make_builtin_scene("boxes", {.seed = 2, .size = 8});
  const TriangleSet set = flatten(scene);
  expect_matches_scalar_loop(set, test::random_rays(set, 4, 2000));
}

TEST(BruteForce, EmptySetNeverHits) {
  const BruteForce bf = BruteForce::build(TriangleSet{});
  EXPECT_FALSE(bf.intersect(Ray{{0, 0, 0}, {0, 0, 1}}).has_value());
  EXPECT_FALSE(bf.occluded(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_EQ(bf.stats().reference_count, 0u);
}

TEST(BruteForce, StatsCountTrianglesAndBytes) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(13, 100, 0.1f, 0.2f));
  const BruteForce bf = BruteForce::build(set);
  EXPECT_EQ(bf.stats().reference_count, 100u);
  EXPECT_GE(bf.stats().memory_bytes, 100u * (9 * sizeof(float) + 2 * sizeof(std::uint32_t)));
  EXPECT_GE(bf.stats().build_ms, 0.0);
  EXPECT_EQ(BruteForce::name(), "brute");
}

}  // namespace
}  // namespace vf
