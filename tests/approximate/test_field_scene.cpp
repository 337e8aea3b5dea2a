// The scene's ObjectFields (FieldScene) in the approximate harness: on built-in scenes, random rays,
// AO rays from surfaces and an AO image are measured against the exact BVH and held to the bounds
// the structure states. Instances share one field per mesh.

#include <gtest/gtest.h>

#include <cstdio>

#include "approximate/harness.hpp"
#include "differential/ray_sets.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::test {
namespace {

using field::FieldScene;
static_assert(ApproximateStructure<FieldScene> && Accelerator<FieldScene>);

struct Measured {
  ApproximationError random, ao;
};

Measured measure_scene(const std::string& name, std::size_t size) {
  const Scene scene = make_builtin_scene(name, {.size = size});
  const TriangleSet set = flatten(scene);
  const Bvh bvh = Bvh::build(set);
  const FieldScene fields = FieldScene::build(scene, {});
  const double diameter = length(set.bounds.extent());
  Measured m;
  m.random = measure_approximation(fields, bvh, random_rays(set, 5, 20000), diameter);
  // Rays leaving surfaces, as AO and shadow rays do: tmin past the start surface's rounding.
  std::vector<Ray> surface = surface_origin_rays(set, 6, 20000);
  for (Ray& ray : surface) ray.tmin = 1e-4f * static_cast<float>(diameter);
  m.ao = measure_approximation(fields, bvh, surface, diameter);
  AoOptions options;
  options.ao_rays = 16;
  m.ao.image_rms = ao_image_rms(fields, bvh, scene, scene.camera_or_default(48, 36), options);
  std::printf("%s: random rays: occlusion %.4f hit %.4f distance rms %.4f; surface rays: occlusion %.4f hit %.4f rms %.4f; AO image rms %.4f\n",
              name.c_str(), m.random.occlusion_disagreement, m.random.hit_disagreement, m.random.distance_rms,
              m.ao.occlusion_disagreement, m.ao.hit_disagreement, m.ao.distance_rms, m.ao.image_rms);
  EXPECT_TRUE(within_bounds(m.random, fields.error_bounds())) << name << " random rays";
  EXPECT_TRUE(within_bounds(m.ao, fields.error_bounds())) << name << " surface rays";
  return m;
}

TEST(FieldScene, StaysWithinItsBoundsOnTheBuiltInScenes) {
  measure_scene("sphere", 2000);
  measure_scene("boxes", 64);
  measure_scene("cornell", 2000);
}

TEST(FieldScene, InstancesOfOneMeshShareOneField) {
  const Scene scene = make_builtin_scene("boxes", {.size = 64});
  const FieldScene fields = FieldScene::build(scene, {.positions = 290, .directions = 16});
  std::size_t used = 0;
  for (std::uint32_t mesh = 0; mesh < scene.meshes.size(); ++mesh) used += fields.mesh_field(mesh) != nullptr;
  EXPECT_EQ(fields.stats().node_count, used);
  EXPECT_LT(used, scene.instances().size());  // 64 boxes of one mesh, a ground
  EXPECT_EQ(fields.stats().leaf_count, scene.instances().size() - 1);  // the ground stays exact
}

// The batch queries answer as the single-ray ones, up to the batch's rounding near cell borders,
// with instances (boxes) and an exact part (the ground) in the scene.
TEST(FieldScene, BatchQueriesAnswerAsSingleRays) {
  const Scene scene = make_builtin_scene("boxes", {.size = 64});
  const TriangleSet set = flatten(scene);
  const FieldScene fields = FieldScene::build(scene, {.positions = 1090, .directions = 16});
  std::vector<Ray> rays = surface_origin_rays(set, 8, 20000);
  for (Ray& ray : rays) ray.tmin = 1e-4f * length(set.bounds.extent());
  const std::vector<Ray> random = random_rays(set, 9, 20000);
  rays.insert(rays.end(), random.begin(), random.end());
  std::vector<std::uint8_t> occluded(rays.size());
  std::vector<Hit> hits(rays.size());
  field::occluded_batch(fields, rays, occluded);
  field::intersect_batch(fields, rays, hits);
  std::size_t occlusion_differs = 0, hit_differs = 0, occluded_count = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const bool one = fields.occluded(rays[i]);
    occluded_count += one ? 1 : 0;
    occlusion_differs += one != (occluded[i] != 0) ? 1 : 0;
    const Hit h = fields.intersect(rays[i]);
    hit_differs += h.found != hits[i].found || (h.found && (h.t != hits[i].t || h.instance != hits[i].instance)) ? 1 : 0;
  }
  EXPECT_GT(occluded_count, rays.size() / 10);
  EXPECT_LE(occlusion_differs, rays.size() / 1000);
  EXPECT_LE(hit_differs, rays.size() / 1000);
}

}  // namespace
}  // namespace vf::test
