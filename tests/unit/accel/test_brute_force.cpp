#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/core/triangle_intersect.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

using test::Triangle;

// Checks BruteForce's answers against its definition, property by property: a reported hit is the
// scalar test's result on that triangle, bit for bit; no triangle is hit nearer, none with a lower
// index as near; a miss means no triangle is hit; occluded() is true exactly when a hit exists.
void expect_the_definition(const TriangleSet& set, const std::vector<Ray>& rays) {
  const BruteForce bf = BruteForce::build(set);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    const Hit got = bf.intersect(ray);
    const WatertightRay wr(ray);
    std::size_t index = set.size();
    for (std::size_t k = 0; k < set.size(); ++k) {
      TriangleHit h{};
      const auto& t = set.triangles[k];
      if (!intersect_triangle(wr, t[0], t[1], t[2], ray.tmin, ray.tmax, h)) continue;
      ASSERT_TRUE(got) << "ray " << i << " hits triangle " << k << " but BruteForce reports a miss";
      ASSERT_GE(h.t, got.t) << "ray " << i << ": triangle " << k << " is nearer";
      if (set.prim[k] == got.prim && set.instance[k] == got.instance) {
        EXPECT_EQ(h.t, got.t);
        EXPECT_EQ(h.u, got.u);
        EXPECT_EQ(h.v, got.v);
        const Vec3f normal = cross(t[1] - t[0], t[2] - t[0]);
        EXPECT_TRUE(got.has_normal && got.normal == normal) << "ray " << i;
        index = std::min(index, k);
      } else if (h.t == got.t) {
        ASSERT_GT(k, index) << "ray " << i << ": an equally near triangle with a lower index";
      }
    }
    ASSERT_EQ(got.found, index < set.size()) << "ray " << i << ": the reported triangle is not hit";
    ASSERT_EQ(bf.occluded(ray), got.found) << "ray " << i;
    hits += got ? 1 : 0;
  }
  EXPECT_GT(hits, rays.size() / 20);
}

TEST(BruteForce, AnswersAreTheDefinitionOnRandomSoup) {
  // 1003 triangles: the last SIMD block is partly empty.
  const TriangleSet set = test::set_from_triangles(test::random_soup(11, 1003, 0.02f, 0.3f));
  std::vector<Ray> rays = test::random_rays(set, 1, 3000);
  const std::vector<Ray> surface = test::surface_origin_rays(set, 2, 1000);
  rays.insert(rays.end(), surface.begin(), surface.end());
  expect_the_definition(set, rays);
}

TEST(BruteForce, TiesGoToTheLowestIndex) {
  // Copies of one triangle at indices 5, 9, 40: every ray through it must report prim 5.
  std::vector<Triangle> triangles = test::random_soup(12, 60, 0.1f, 0.2f);
  const Triangle repeated{Vec3f{0.1f, 0.1f, 0.5f}, Vec3f{0.9f, 0.1f, 0.5f}, Vec3f{0.5f, 0.9f, 0.5f}};
  for (std::size_t i : {5u, 9u, 40u}) triangles[i] = repeated;
  const TriangleSet set = test::set_from_triangles(triangles);
  const BruteForce bf = BruteForce::build(set);
  const Hit h = bf.intersect(Ray{{0.5f, 0.4f, -1.0f}, {0, 0, 1}});
  ASSERT_TRUE(h);
  EXPECT_EQ(h.prim, 5u);
  EXPECT_FLOAT_EQ(h.t, 1.5f);
  // Rays aimed at the repeated triangle: most hit it, each a three-way tie.
  Rng rng(3);
  std::vector<Ray> rays;
  for (int i = 0; i < 2000; ++i) {
    const Vec3f org = test::point_around(rng, set.bounds, 0.5f);
    rays.push_back(Ray{org, test::random_point_on(rng, repeated) - org});
  }
  expect_the_definition(set, rays);
}

TEST(BruteForce, ReportsPrimAndObjectOfInstancedMeshes) {
  const Scene scene = make_builtin_scene("boxes", {.seed = 2, .size = 8});
  const TriangleSet set = flatten(scene);
  expect_the_definition(set, test::random_rays(set, 4, 2000));
}

TEST(BruteForce, EmptySetNeverHits) {
  const BruteForce bf = BruteForce::build(TriangleSet{});
  EXPECT_FALSE(bf.intersect(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_FALSE(bf.occluded(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_EQ(bf.stats().reference_count, 0u);
}

TEST(BruteForce, StatsCountTrianglesAndBytes) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(13, 100, 0.1f, 0.2f));
  const BruteForce bf = BruteForce::build(set);
  EXPECT_EQ(bf.stats().reference_count, 100u);
  EXPECT_GE(bf.stats().memory_bytes, 100u * (9 * sizeof(float) + 2 * sizeof(std::uint32_t)));
  EXPECT_EQ(BruteForce::name(), "brute");
}

}  // namespace
}  // namespace vf
