#include <gtest/gtest.h>

#include <cmath>

#include "test_scenes.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/render/ray_sets.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

bool same_ray(const Ray& a, const Ray& b) {
  return a.org == b.org && a.dir == b.dir && a.tmin == b.tmin && a.tmax == b.tmax;
}

std::size_t count_hits(const BruteForce& accel, const std::vector<Ray>& rays) {
  std::size_t hits = 0;
  for (const Ray& ray : rays) hits += accel.intersect(ray).found;
  return hits;
}

TEST(RaySets, PrimaryRaysAreThePixelCentresInRowMajorOrder) {
  const Scene scene = make_builtin_scene("cornell", {.size = 100});
  const Camera camera = scene.camera_or_default(13, 7);
  const std::vector<Ray> rays = make_primary_rays(scene, camera);
  ASSERT_EQ(rays.size(), 13u * 7u);
  const PinholeCamera pinhole(camera);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 13; ++x) EXPECT_TRUE(same_ray(rays[y * 13 + x], pinhole.generate(x + 0.5f, y + 0.5f)));
}

TEST(RaySets, AoRaysAreExactlyTheRaysRenderAoTraces) {
  const Scene scene = make_builtin_scene("cornell", {.size = 200});
  const Camera camera = scene.camera_or_default(24, 18);
  AoOptions opt;
  opt.ao_rays = 4;
  opt.max_distance = 1.5f;
  opt.seed = 9;
  opt.tile_size = 64;  // one tile: on one thread, render_ao queries in pixel order
  opt.progress = false;
  const BruteForce oracle = test::scene_oracle(scene);
  const test::RecordingOccluder recorder(oracle);
  {
    const ThreadLimit limit(1);
    render_ao(oracle, recorder, scene, camera, opt);
  }
  const std::vector<Ray> rays = make_ao_rays(oracle, scene, camera, opt.ao_rays, opt.max_distance, opt.seed);
  ASSERT_EQ(rays.size(), recorder.queries().size());
  ASSERT_GT(rays.size(), 0u);
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) mismatches += !same_ray(rays[i], recorder.queries()[i]);
  EXPECT_EQ(mismatches, 0u);
}

TEST(RaySets, AoRaysLeaveTheSurfaceIntoItsHemisphere) {
  const Scene scene = test::plane_scene(2.0f);
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = test::camera_looking_at({0, 10, 0}, {0, 0, 0}, 30, 20, 60.0f);
  const std::size_t hits = count_hits(accel, make_primary_rays(scene, camera));
  const std::vector<Ray> rays = make_ao_rays(accel, scene, camera, 7, 3.0f, 5);
  ASSERT_EQ(rays.size(), 7 * hits);
  for (const Ray& ray : rays) {
    EXPECT_GT(ray.org.y, 0.0f);
    EXPECT_LT(ray.org.y, 1e-3f);
    EXPECT_GE(ray.dir.y, 0.0f);
    EXPECT_NEAR(length(ray.dir), 1.0f, 1e-5f);
    EXPECT_EQ(ray.tmin, 0.0f);
    EXPECT_EQ(ray.tmax, 3.0f);
    EXPECT_FALSE(accel.occluded(ray));
  }
  EXPECT_EQ(make_ao_rays(accel, scene, camera, 7, 3.0f, 5).front().dir, rays.front().dir);
  EXPECT_NE(make_ao_rays(accel, scene, camera, 7, 3.0f, 6).front().dir, rays.front().dir);
  EXPECT_THROW(make_ao_rays(accel, scene, camera, 0, 3.0f, 5), Error);
  EXPECT_THROW(make_ao_rays(accel, scene, camera, 4, 0.0f, 5), Error);
}

// Where a ray's segment ends.
Vec3f end_point(const Ray& ray) { return ray.org + ray.dir * ray.tmax; }

TEST(RaySets, ShadowRaysStopJustShortOfAPointLight) {
  const Scene scene = make_builtin_scene("cornell", {.size = 200});
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = scene.camera_or_default(20, 15);
  const std::vector<Ray> rays = make_shadow_rays(accel, scene, camera, 3);
  ASSERT_EQ(rays.size(), count_hits(accel, make_primary_rays(scene, camera)));
  const Vec3f light = scene.point_lights.at(0).position;
  std::size_t lit = 0;
  for (const Ray& ray : rays) {
    const float distance = length(light - ray.org);
    EXPECT_NEAR(length(end_point(ray) - light), 1e-4f * distance, 1e-5f);
    EXPECT_LT(ray.tmax, distance);
    lit += !accel.occluded(ray);
  }
  // Most of the room sees the light; the parts facing away from it (the ceiling) do not.
  EXPECT_GT(lit, rays.size() / 2);
  EXPECT_LT(lit, rays.size());
}

TEST(RaySets, ShadowRaysAimAtTheFacingSideOfSphereLights) {
  Scene scene = test::plane_scene(2.0f);
  scene.sphere_lights.push_back(SphereLight{{0.0f, 5.0f, 0.0f}, 1.0f, Vec3f{1.0f}});
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = test::camera_looking_at({0, 10, 0.5f}, {0, 0, 0}, 16, 16, 20.0f);
  const std::vector<Ray> rays = make_shadow_rays(accel, scene, camera, 3);
  ASSERT_EQ(rays.size(), 256u);
  for (const Ray& ray : rays) {
    const Vec3f to_end = end_point(ray) - Vec3f{0.0f, 5.0f, 0.0f};
    EXPECT_NEAR(length(to_end), 1.0f, 1e-3f);
    EXPECT_GE(dot(to_end, ray.org - Vec3f{0.0f, 5.0f, 0.0f}), 0.0f);
    EXPECT_FALSE(accel.occluded(ray));  // nothing between the plane and the light
  }
}

TEST(RaySets, ShadowRaysWithoutLightsAimAboveTheScene) {
  const Scene open = test::plane_scene(2.0f);
  const Camera camera = test::camera_looking_at({0, 10, 0}, {0, 0, 0}, 8, 8, 20.0f);
  const BruteForce open_oracle = test::scene_oracle(open);
  for (const Ray& ray : make_shadow_rays(open_oracle, open, camera, 1)) {
    EXPECT_NEAR(length(end_point(ray) - Vec3f{0.0f, 4.0f, 0.0f}), 0.0f, 1e-3f);  // one bounds extent (4) up
    EXPECT_FALSE(open_oracle.occluded(ray));
  }
  const Scene box = test::closed_box_scene();
  const BruteForce box_accel = test::scene_oracle(box);
  const std::vector<Ray> inside = make_shadow_rays(box_accel, box, test::camera_looking_at({0, 0, 0}, {0, -1, 0}, 8, 8, 60.0f), 1);
  ASSERT_EQ(inside.size(), 64u);
  for (const Ray& ray : inside) EXPECT_TRUE(box_accel.occluded(ray));  // the target is outside the closed box
}

TEST(RaySets, RandomRaysJoinTwoPointsOfTheBoundingSphere) {
  Bounds3f bounds;
  bounds.extend(Vec3f{0.0f, 0.0f, 0.0f});
  bounds.extend(Vec3f{1.0f, 2.0f, 3.0f});
  const Vec3f center = bounds.center();
  const float radius = 0.5f * length(bounds.extent());
  const std::vector<Ray> rays = make_random_rays(bounds, 20000, 4);
  ASSERT_EQ(rays.size(), 20000u);
  Vec3f mean_dir{0.0f};
  for (const Ray& ray : rays) {
    EXPECT_NEAR(length(ray.org - center), radius, 1e-5f * radius * 10);
    EXPECT_NEAR(length(end_point(ray) - center), radius, 1e-5f * radius * 10);
    EXPECT_NEAR(length(ray.dir), 1.0f, 1e-5f);
    EXPECT_EQ(ray.tmin, 0.0f);
    EXPECT_GT(ray.tmax, 0.0f);
    mean_dir += ray.dir * (1.0f / 20000.0f);
  }
  EXPECT_LT(length(mean_dir), 0.03f);  // isotropic
  // Ray i depends on (seed, i) only.
  const std::vector<Ray> fewer = make_random_rays(bounds, 100, 4);
  for (std::size_t i = 0; i < fewer.size(); ++i) EXPECT_TRUE(same_ray(fewer[i], rays[i]));
  EXPECT_FALSE(same_ray(make_random_rays(bounds, 1, 5)[0], rays[0]));
  EXPECT_THROW(make_random_rays(Bounds3f{}, 10, 1), Error);
  EXPECT_THROW(make_random_rays(bounds, std::size_t{1} << 60, 1), Error);  // refused before allocating
}

}  // namespace
}  // namespace vf
