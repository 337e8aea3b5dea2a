// The offset rule secondary rays leave surfaces by (SurfaceSpawner): no self-hits (acne) and no rays
// slipping through a perpendicular surface at corners (leaks), with tmin exclusive.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "test_scenes.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/render/sample_rays.hpp"

namespace vf {
namespace {

// Directions of the hemisphere about `normal`, uniformly, leaving out those within 1e-3 of the plane
// x = 0 or y = 0 (grazing the crease's own surfaces, where either answer is right).
std::vector<Vec3f> hemisphere_directions(const Vec3f& normal, int count) {
  Rng rng(99, 1);
  std::vector<Vec3f> out;
  while (static_cast<int>(out.size()) < count) {
    Vec3f d = uniform_sphere(rng.uniform(), rng.uniform());
    if (dot(d, normal) < 0.0f) d = -d;
    if (std::fabs(d.x) > 1e-3f && std::fabs(d.y) > 1e-3f) out.push_back(d);
  }
  return out;
}

template <class S>
void check_corner_hits(const S& structure, const Scene& scene, const char* name) {
  const SurfaceSpawner spawner(scene);
  int leaks = 0, acne = 0, checked = 0;
  // Camera rays aimed exactly at points of the crease line x = y = 0, from either side.
  Rng rng(7, 2);
  for (int i = 0; i < 200; ++i) {
    const float z = rng.uniform() * 1.6f - 0.8f;
    const Vec3f target{0.0f, 0.0f, z};
    const Vec3f from{0.05f + rng.uniform(), 0.05f + rng.uniform(), z + rng.uniform() - 0.5f};
    const Ray primary{from, target - from};
    const Hit hit = structure.intersect(primary);
    ASSERT_TRUE(hit) << name;
    const SurfacePoint point = spawner.surface_point(primary, hit);
    for (const Vec3f& dir : hemisphere_directions(point.normal, 64)) {
      // Leaving the floor (normal +y), a ray towards -x meets the wall; leaving the wall (normal +x),
      // a ray towards -y meets the floor. Any other ray escapes.
      const bool into_other_surface = point.normal.y > 0.5f ? dir.x < 0.0f : dir.y < 0.0f;
      const bool occluded = structure.occluded(Ray{point.position, dir});
      leaks += into_other_surface && !occluded;
      acne += !into_other_surface && occluded;
      ++checked;
    }
  }
  EXPECT_EQ(leaks, 0) << name << ": rays into the perpendicular surface slipped through, of " << checked;
  EXPECT_EQ(acne, 0) << name << ": rays leaving the corner hit a surface they start on, of " << checked;
}

TEST(SurfaceSpawner, HitsExactlyOnACornerLeaveNeitherAcneNorLeaks) {
  const Scene scene = test::crease_scene(1.0f);
  check_corner_hits(test::scene_oracle(scene), scene, "brute");
  check_corner_hits(Bvh::build(flatten(scene)), scene, "bvh");
}

TEST(SurfaceSpawner, ABoxStandingOnTheFloorOfAClosedRoomLeaksNothing) {
  // The closed room [-1, 1]^3 with a closed box standing on its floor: every AO ray from any visible
  // point meets a wall, the box or the floor, so every pixel is exactly 0, the contact edges included.
  Scene scene = test::closed_box_scene();
  TriangleMesh box = scene.meshes[0];
  box.name = "crate";
  for (Vec3f& p : box.positions) p = Vec3f{p.x * 0.3f, p.y * 0.3f + (-1.0f + 0.3f), p.z * 0.3f};
  scene.meshes.push_back(box);
  scene.add_instance(1);
  const Bvh bvh = Bvh::build(flatten(scene));
  // Looking down at the crate's foot from inside the room.
  const Camera camera = test::camera_looking_at({0.6f, 0.5f, 0.1f}, {0.3f, -1.0f, 0.0f}, 48, 48, 50.0f);
  AoOptions opt;
  opt.ao_rays = 64;
  opt.progress = false;
  for (const Vec3f& p : render_ao(bvh, bvh, scene, camera, opt).pixels) ASSERT_EQ(p, Vec3f{0.0f});
}

TEST(SurfaceSpawner, TheOffsetStaysTinyAndOnTheRaysSide) {
  const Scene scene = test::plane_scene(10.0f);
  const SurfaceSpawner spawner(scene);
  const BruteForce oracle = test::scene_oracle(scene);
  for (const float height : {1.0f, -1.0f}) {
    const Ray primary{{0.3f, height, 0.2f}, {0.1f, -height, 0.05f}};
    const Hit hit = oracle.intersect(primary);
    ASSERT_TRUE(hit);
    const SurfacePoint point = spawner.surface_point(primary, hit);
    EXPECT_EQ(point.normal.y, height > 0.0f ? 1.0f : -1.0f);
    EXPECT_GT(point.position.y * height, 0.0f) << "lifted to the side the ray came from";
    EXPECT_LT(std::fabs(point.position.y), 1e-3f);
    EXPECT_LT(length(point.position - (primary.org + primary.dir * hit.t)), 1e-3f);
  }
}

}  // namespace
}  // namespace vf
