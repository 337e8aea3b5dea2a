#include <gtest/gtest.h>

#include <cmath>

#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/error.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/scenes/builtin.hpp"
#include "visfield/select/path_rays.hpp"
#include "visfield/select/workload.hpp"

namespace vf {
namespace {

bool same_ray(const Ray& a, const Ray& b) { return a.org == b.org && a.dir == b.dir && a.tmin == b.tmin && a.tmax == b.tmax; }

bool same_rays(const std::vector<Ray>& a, const std::vector<Ray>& b, std::size_t count) {
  if (a.size() < count || b.size() < count) return false;
  for (std::size_t i = 0; i < count; ++i)
    if (!same_ray(a[i], b[i])) return false;
  return true;
}

struct Fixture {
  Scene scene = make_builtin_scene("cornell", {.size = 300});
  TriangleSet triangles = flatten(scene);
};

TEST(PathRays, GivesExactlyTheRequestedCountWithShadowAndBounceRays) {
  const Fixture f;
  const UniformGrid grid = UniformGrid::build(f.triangles);
  const QuerySet rays = make_path_rays(grid, f.scene, 1000, {.max_bounces = 2, .seed = 3});
  EXPECT_EQ(rays.size(), 1000u);
  // In a closed room nearly every ray hits, so about half the queries are shadow rays.
  EXPECT_GT(rays.shadow.size(), 300u);
  EXPECT_GT(rays.closest.size(), 300u);
  const Vec3f eye = f.scene.camera_or_default(0, 0).position;
  std::size_t from_eye = 0;
  for (const Ray& ray : rays.closest) {
    EXPECT_NEAR(length(ray.dir), 1.0f, 1e-4f);
    from_eye += ray.org == eye;
  }
  EXPECT_GT(from_eye, 50u);                       // camera rays
  EXPECT_LT(from_eye, rays.closest.size() / 2);   // and bounces
  for (const Ray& ray : rays.shadow) {
    EXPECT_TRUE(std::isfinite(ray.tmax));
    EXPECT_NEAR(length(ray.dir), 1.0f, 1e-4f);
  }
}

TEST(PathRays, WithoutBouncesOnlyCameraRaysAreTraced) {
  const Fixture f;
  const BruteForce brute = BruteForce::build(f.triangles);
  const QuerySet rays = make_path_rays(brute, f.scene, 400, {.max_bounces = 0, .seed = 1});
  const Vec3f eye = f.scene.camera_or_default(0, 0).position;
  for (const Ray& ray : rays.closest) EXPECT_EQ(ray.org, eye);
  EXPECT_GE(rays.closest.size(), rays.shadow.size());
}

TEST(PathRays, DoNotDependOnTheStructureOrTheThreadCount) {
  const Fixture f;
  const UniformGrid grid = UniformGrid::build(f.triangles);
  const KdTree tree = KdTree::build(f.triangles);
  const BruteForce brute = BruteForce::build(f.triangles);
  const QuerySet a = make_path_rays(grid, f.scene, 3000, {.max_bounces = 3, .seed = 5});
  const QuerySet b = make_path_rays(tree, f.scene, 3000, {.max_bounces = 3, .seed = 5});
  QuerySet c;
  {
    const ThreadLimit one(1);
    c = make_path_rays(brute, f.scene, 3000, {.max_bounces = 3, .seed = 5});
  }
  ASSERT_EQ(a.closest.size(), b.closest.size());
  ASSERT_EQ(a.closest.size(), c.closest.size());
  EXPECT_TRUE(same_rays(a.closest, b.closest, a.closest.size()));
  EXPECT_TRUE(same_rays(a.shadow, b.shadow, a.shadow.size()));
  EXPECT_TRUE(same_rays(a.closest, c.closest, a.closest.size()));
  EXPECT_TRUE(same_rays(a.shadow, c.shadow, a.shadow.size()));
}

TEST(PathRays, AShorterSetIsAPrefixAndTheSeedMatters) {
  const Fixture f;
  const UniformGrid grid = UniformGrid::build(f.triangles);
  const QuerySet longer = make_path_rays(grid, f.scene, 5000, {.seed = 2});
  const QuerySet shorter = make_path_rays(grid, f.scene, 700, {.seed = 2});
  EXPECT_EQ(shorter.size(), 700u);
  EXPECT_TRUE(same_rays(longer.closest, shorter.closest, shorter.closest.size()));
  EXPECT_TRUE(same_rays(longer.shadow, shorter.shadow, shorter.shadow.size()));
  const QuerySet other = make_path_rays(grid, f.scene, 700, {.seed = 3});
  EXPECT_FALSE(same_rays(other.closest, shorter.closest, 10));
}

TEST(PathRays, RefuseBadBounceCounts) {
  const Fixture f;
  const BruteForce brute = BruteForce::build(f.triangles);
  EXPECT_THROW(make_path_rays(brute, f.scene, 10, {.max_bounces = -1}), Error);
  EXPECT_THROW(make_path_rays(brute, f.scene, 10, {.max_bounces = 17}), Error);
  EXPECT_EQ(make_path_rays(brute, f.scene, 0).size(), 0u);
}

TEST(Queries, RandomKindIsTheRandomRaySetAndPathKindThePathSet) {
  const Fixture f;
  const BruteForce brute = BruteForce::build(f.triangles);
  const QuerySet random = make_queries(RayKind::random, brute, f.scene, f.triangles.bounds, 250, 4, 2);
  EXPECT_EQ(random.closest.size(), 250u);
  EXPECT_TRUE(random.shadow.empty());
  EXPECT_TRUE(same_rays(random.closest, make_random_rays(f.triangles.bounds, 250, 4), 250));
  const QuerySet path = make_queries(RayKind::path, brute, f.scene, f.triangles.bounds, 250, 4, 1);
  const QuerySet expected = make_path_rays(brute, f.scene, 250, {.max_bounces = 1, .seed = 4});
  EXPECT_TRUE(same_rays(path.closest, expected.closest, expected.closest.size()));
  EXPECT_EQ(path.shadow.size(), expected.shadow.size());
}

TEST(RayKinds, NamesRoundTripAndOnlyTwoAreCalibrated) {
  for (RayKind kind : kRayKinds) EXPECT_EQ(parse_ray_kind(ray_kind_name(kind)), kind);
  EXPECT_FALSE(parse_ray_kind("Random").has_value());
  EXPECT_EQ(calibrated_kind_index(RayKind::random), 0u);
  EXPECT_EQ(calibrated_kind_index(RayKind::path), 1u);
  EXPECT_THROW(calibrated_kind_index(RayKind::ao), Error);
  EXPECT_TRUE(is_occlusion_kind(RayKind::shadow));
  EXPECT_FALSE(is_occlusion_kind(RayKind::path));
}

}  // namespace
}  // namespace vf
