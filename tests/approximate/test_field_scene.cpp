// The scene's ObjectFields (FieldScene) in the approximate harness: on built-in scenes, random rays,
// AO rays from surfaces and an AO image are measured against the exact BVH and held to the bounds
// the structure states. Instances share one field per mesh.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "approximate/harness.hpp"
#include "differential/ray_sets.hpp"
#include "support/turned_boxes.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
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

// The batch queries answer as the single-ray ones bit for bit, with instances (boxes, rotated and
// scaled below), an exact part (the ground) and a normal field in the scene: 64 objects (found
// through the tree) and 9 (each sphere tested on lanes).
class FieldSceneBatch : public ::testing::TestWithParam<std::size_t> {};

TEST_P(FieldSceneBatch, AnswersAsSingleRaysBitForBit) {
  const Scene scene = turned_boxes(GetParam());
  const TriangleSet set = flatten(scene);
  const FieldScene fields = FieldScene::build(scene, {.positions = 1090, .directions = 16, .normals = field::NormalStorage::oct16});
  std::vector<Ray> rays = surface_origin_rays(set, 8, 20000);
  for (Ray& ray : rays) ray.tmin = 1e-4f * length(set.bounds.extent());
  const std::vector<Ray> random = random_rays(set, 9, 19999);
  rays.insert(rays.end(), random.begin(), random.end());
  std::vector<std::uint8_t> occluded(rays.size());
  std::vector<Hit> hits(rays.size());
  field::occluded_batch(fields, rays, occluded);
  field::intersect_batch(fields, rays, hits);
  std::size_t occlusion_differs = 0, hit_differs = 0, occluded_count = 0, field_hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const bool one = fields.occluded(rays[i]);
    occluded_count += one ? 1 : 0;
    occlusion_differs += one != (occluded[i] != 0) ? 1 : 0;
    const Hit h = fields.intersect(rays[i]);
    hit_differs += h.found != hits[i].found ||
                           (h.found && (h.t != hits[i].t || h.instance != hits[i].instance || h.has_normal != hits[i].has_normal ||
                                        !(h.normal == hits[i].normal)))
                       ? 1
                       : 0;
    if (h.found && !h.has_triangle()) {
      ++field_hits;
      EXPECT_TRUE(h.has_normal);
    }
  }
  EXPECT_GT(occluded_count, rays.size() / 10);
  EXPECT_GT(field_hits, rays.size() / 20);
  EXPECT_EQ(occlusion_differs, 0u);
  EXPECT_EQ(hit_differs, 0u);
}

INSTANTIATE_TEST_SUITE_P(Objects, FieldSceneBatch, ::testing::Values(std::size_t{64}, std::size_t{9}));

// A small exact part (here the ground's two triangles) is tested a packet of rays at a time in the
// batches and through its BVH by the single-ray query: the same answers on rays made to be hard for
// the watertight test — through the ground's corners and along its shared diagonal (edge functions
// of 0), with directions whose largest components tie, ending exactly on the ground or just short
// of it, starting on it; occlusion and closest hits (t, u, v, triangle, object, normal).
TEST(FieldScene, ASmallExactPartAnswersInPacketsAsThroughItsBvh) {
  const Scene scene = turned_boxes(4);
  const TriangleSet set = flatten(scene);
  const FieldScene fields = FieldScene::build(scene, {.positions = 290, .directions = 8});
  TriangleSet ground;
  for (std::size_t k = 0; k < set.size(); ++k)
    if (scene.meshes[scene.instance(set.instance[k]).mesh].occluder == MeshOccluder::exact) ground.triangles.push_back(set.triangles[k]);
  ASSERT_EQ(ground.triangles.size(), 2u);
  std::vector<Vec3f> targets;
  for (const std::array<Vec3f, 3>& t : ground.triangles)
    for (int k = 0; k < 3; ++k) {
      targets.push_back(t[k]);
      for (const float w : {0.5f, 0.25f, 1.0f / 3.0f}) targets.push_back(t[k] + (t[(k + 1) % 3] - t[k]) * w);
    }
  Rng rng(71, 0, 0);
  for (int k = 0; k < 64; ++k) targets.push_back(ground.triangles[0][0] * rng.uniform() + ground.triangles[0][1] * rng.uniform() * 0.5f);
  const Vec3f directions[] = {{1, 1, 1},   {-1, -1, -1}, {1, -1, 1},  {0, -1, 0}, {0, 1, 0},  {1, -1, 0}, {-1, -1, 0},
                              {0, -1, -1}, {2, -1, 2},   {1, -2, -1}, {0.5f, -1, 0.5f}, {1, 0, 0}, {0, 0, -1}, {-1, -1, 1}};
  std::vector<Ray> rays;
  const float size = length(set.bounds.extent());
  for (const Vec3f& target : targets)
    for (const Vec3f& d : directions) {
      const float reach = 0.3f * size / length(d);  // from + reach · d is the target
      const Vec3f from = target - d * reach;
      rays.push_back(Ray{from, d, 0.0f, reach});                       // ends on the ground
      rays.push_back(Ray{from, d, 0.0f, std::nextafter(reach, 0.0f)});  // just short of it
      rays.push_back(Ray{from, d, 0.0f, 2.0f * reach});                 // through it
      rays.push_back(Ray{target, d, 0.0f, size});                       // from it
      rays.push_back(Ray{target, -d, 0.0f, size});
    }
  std::vector<std::uint8_t> occluded(rays.size());
  field::occluded_batch(fields, rays, occluded);
  std::vector<Hit> closest(rays.size());
  field::intersect_batch(fields, rays, closest);
  std::size_t differ = 0, hits = 0, closest_differ = 0, ground_hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const bool one = fields.occluded(rays[i]);
    hits += one ? 1 : 0;
    differ += one != (occluded[i] != 0) ? 1 : 0;
    const Hit h = fields.intersect(rays[i]), &b = closest[i];
    ground_hits += h.has_triangle() ? 1 : 0;
    const auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x); };
    closest_differ += h.found != b.found || (h.found && (bits(h.t) != bits(b.t) || bits(h.u) != bits(b.u) || bits(h.v) != bits(b.v) ||
                                                         h.prim != b.prim || h.instance != b.instance || bits(h.normal.x) != bits(b.normal.x) ||
                                                         bits(h.normal.y) != bits(b.normal.y) || bits(h.normal.z) != bits(b.normal.z)))
                          ? 1
                          : 0;
  }
  EXPECT_GT(hits, rays.size() / 4);
  EXPECT_LT(hits, rays.size() * 9 / 10);
  EXPECT_GT(ground_hits, rays.size() / 5);
  EXPECT_EQ(differ, 0u) << "of " << rays.size() << " rays";
  EXPECT_EQ(closest_differ, 0u) << "closest hits, of " << rays.size() << " rays";
}

// A field hit's normal is the surface's: on the boxes, within the normal field's and the sampling's
// error of the exact hit's normal (measured: most within a degree, a few at box edges far off).
TEST(FieldScene, FieldHitsCarryTheSurfaceNormal) {
  const Scene scene = make_builtin_scene("boxes", {.size = 16});
  const TriangleSet set = flatten(scene);
  const Bvh bvh = Bvh::build(set);
  const FieldScene fields = FieldScene::build(scene, {.positions = 4226, .directions = 32, .normals = field::NormalStorage::oct32});
  // Rays from 3 radii away aimed at points near the boxes' centres.
  std::vector<Ray> rays;
  Rng rng(11);
  for (const Instance& object : scene.instances()) {
    if (scene.meshes[object.mesh].occluder == MeshOccluder::exact) continue;
    const Bounds3f box = object.transform.apply_bounds(scene.meshes[object.mesh].bounds());
    const Vec3f centre = (box.lo + box.hi) * 0.5f;
    const float radius = 0.5f * length(box.extent());
    for (int k = 0; k < 500; ++k) {
      const Vec3f org = centre + uniform_sphere(rng.uniform(), rng.uniform()) * (3.0f * radius);
      const Vec3f target = centre + uniform_sphere(rng.uniform(), rng.uniform()) * (0.3f * radius);
      rays.push_back(Ray{org, target - org, 0.0f, 10.0f});
    }
  }
  std::size_t compared = 0, close = 0;
  for (const Ray& ray : rays) {
    const Hit exact = bvh.intersect(ray), approx = fields.intersect(ray);
    if (!exact || !approx || approx.has_triangle() || exact.instance != approx.instance) continue;
    ++compared;
    close += dot(normalize(exact.normal), normalize(approx.normal)) > std::cos(5.0f * 3.14159265f / 180.0f) ? 1 : 0;
  }
  ASSERT_GT(compared, 1000u);
  std::printf("normals within 5 degrees: %zu of %zu\n", close, compared);
  EXPECT_GT(static_cast<double>(close) / static_cast<double>(compared), 0.9) << close << " of " << compared;
}

/// turned_boxes(400) with every third box made of a second mesh (the box flattened to 60% of its
/// height, so a field of its own): the tree's leaves hold objects of either field, side by side.
Scene boxes_of_two_meshes() {
  Scene scene = turned_boxes(400);
  std::uint32_t box_mesh = 0;
  while (scene.meshes[box_mesh].occluder == MeshOccluder::exact) ++box_mesh;
  TriangleMesh flat = scene.meshes[box_mesh];
  flat.name += " flattened";
  for (Vec3f& p : flat.positions) p.y *= 0.6f;
  scene.meshes.push_back(flat);
  const auto flat_mesh = static_cast<std::uint32_t>(scene.meshes.size() - 1);
  for (const Instance& object : std::vector<Instance>(scene.instances().begin(), scene.instances().end())) {
    if (object.mesh != box_mesh || object.id % 3 != 1) continue;
    scene.remove_instance(object.id);
    scene.add_instance(flat_mesh, object.transform);
  }
  return scene;
}

/// builtin:boxes' box on its ground, copied onto a 20 x 20 lattice of spacing 1.15 box widths, each
/// turned about +y and scaled by 0.8-1.1, every third copy of the box flattened to 60% of its height
/// (a second field): copies in rows, as the grid over the objects is made for.
Scene boxes_on_a_lattice() {
  Scene scene = make_builtin_scene("boxes", {.size = 1});
  const Instance first = *std::find_if(scene.instances().begin(), scene.instances().end(),
                                       [&](const Instance& i) { return scene.meshes[i.mesh].occluder != MeshOccluder::exact; });
  TriangleMesh flat = scene.meshes[first.mesh];
  flat.name += " flattened";
  for (Vec3f& p : flat.positions) p.y *= 0.6f;
  scene.meshes.push_back(flat);
  const auto flat_mesh = static_cast<std::uint32_t>(scene.meshes.size() - 1);
  Bounds3f box;
  for (const Vec3f& p : scene.meshes[first.mesh].positions) box.extend(first.transform.apply_point(p));
  const float step = 1.15f * (box.hi.x - box.lo.x);
  Rng rng(31);
  for (int k = 1; k < 400; ++k) {
    Transform t = first.transform;
    t.translation.x += step * static_cast<float>(k % 20);
    t.translation.z += step * static_cast<float>(k / 20);
    t.rotation = Mat3::rotation(Vec3f{0.0f, 1.0f, 0.0f}, 360.0f * rng.uniform()) * t.rotation;
    t.scale *= 0.8f + 0.3f * rng.uniform();
    scene.add_instance(k % 3 == 1 ? flat_mesh : first.mesh, t);
  }
  return scene;
}

class FieldSceneTree : public ::testing::TestWithParam<int> {};

// The tree over the objects' spheres, and the grid that routes a batch's rays to lists of objects
// before it, give each ray the objects that testing every sphere gives it, so the answers are the
// same bit for bit, single rays and batches, closest hits and occlusion: on 400 boxes, some rotated
// and scaled, with rays from surfaces, random rays through the scene and rays from far outside it;
// with one field (1), two among the tree's leaves (2), and two on a lattice, where the grid routes
// rays to lists holding both (3).

TEST_P(FieldSceneTree, AnswersAsTestingEverySphere) {
  const Scene scene = GetParam() == 1 ? turned_boxes(400) : GetParam() == 2 ? boxes_of_two_meshes() : boxes_on_a_lattice();
  const TriangleSet set = flatten(scene);
  const field::ObjectFieldConfig config{.positions = 290, .directions = 16};
  const FieldScene grid = FieldScene::build(scene, config, {}, "", field::FieldMeshes::all, field::ObjectCull::grid);
  const FieldScene tree = FieldScene::build(scene, config, {}, "", field::FieldMeshes::all, field::ObjectCull::tree);
  const FieldScene each = FieldScene::build(scene, config, {}, "", field::FieldMeshes::all, field::ObjectCull::each);
  ASSERT_GT(tree.stats().leaf_count, 300u);
  ASSERT_EQ(tree.stats().node_count, GetParam() == 1 ? 1u : 2u);  // fields
  EXPECT_GT(tree.stats().memory_bytes, each.stats().memory_bytes);  // the tree's nodes
  std::vector<Ray> rays = surface_origin_rays(set, 11, 20000);
  for (Ray& ray : rays) ray.tmin = 1e-4f * length(set.bounds.extent());
  const std::vector<Ray> random = random_rays(set, 12, 20000);
  rays.insert(rays.end(), random.begin(), random.end());
  // From 100 scene sizes away, towards the scene: long rays across many spheres.
  Rng rng(13);
  const Vec3f centre = set.bounds.center();
  const float size = length(set.bounds.extent());
  for (int k = 0; k < 2000; ++k) {
    const Vec3f from = centre + uniform_sphere(rng.uniform(), rng.uniform()) * (100.0f * size);
    const Vec3f to = centre + Vec3f{rng.uniform() - 0.5f, rng.uniform() * 0.1f, rng.uniform() - 0.5f} * size;
    rays.push_back(Ray{from, to - from, 0.0f, 2.0f});
  }
  // On the lattice the grid takes a share of the rays (or it would be compared with nothing); among
  // the piled boxes its lists would be too long: no grid. The tree alone routes none.
  if (GetParam() == 3) {
    EXPECT_GT(grid.stats().memory_bytes, tree.stats().memory_bytes);  // the grid's lists
    EXPECT_GT(grid.routed_by_grid(rays), rays.size() / 4);
  }
  EXPECT_EQ(tree.routed_by_grid(rays), 0u);
  std::vector<std::uint8_t> occluded_grid(rays.size()), occluded_tree(rays.size()), occluded_each(rays.size());
  std::vector<Hit> hits_grid(rays.size()), hits_tree(rays.size()), hits_each(rays.size());
  field::occluded_batch(grid, rays, occluded_grid);
  field::occluded_batch(tree, rays, occluded_tree);
  field::occluded_batch(each, rays, occluded_each);
  field::intersect_batch(grid, rays, hits_grid);
  field::intersect_batch(tree, rays, hits_tree);
  field::intersect_batch(each, rays, hits_each);
  const auto same = [](const Hit& a, const Hit& b) {
    return a.found == b.found && (!a.found || (a.t == b.t && a.instance == b.instance && a.prim == b.prim));
  };
  // Tree against every sphere, single rays against batches.
  std::size_t differ = 0, batch_differs = 0, occluded = 0, field_hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const bool one = each.occluded(rays[i]);
    occluded += one ? 1 : 0;
    differ += tree.occluded(rays[i]) != one || occluded_tree[i] != occluded_each[i] || occluded_grid[i] != occluded_each[i] ? 1 : 0;
    const Hit h = each.intersect(rays[i]);
    field_hits += h.found && !h.has_triangle() ? 1 : 0;
    differ += !same(tree.intersect(rays[i]), h) || !same(hits_tree[i], hits_each[i]) || !same(hits_grid[i], hits_each[i]) ? 1 : 0;
    batch_differs += (occluded_each[i] != 0) != one || !same(hits_each[i], h) ? 1 : 0;
  }
  EXPECT_EQ(batch_differs, 0u);
  EXPECT_GT(occluded, rays.size() / 10);
  EXPECT_GT(field_hits, rays.size() / 20);
  EXPECT_EQ(differ, 0u);
  std::printf("routed by the grid: %zu of %zu rays\n", grid.routed_by_grid(rays), rays.size());
}

INSTANTIATE_TEST_SUITE_P(Fields, FieldSceneTree, ::testing::Values(1, 2, 3));

// Two objects in one place answer with equal t: the closest hit is the first object's (the lower
// index), whichever order the walk takes them in, single rays and batches, through the tree and
// testing every sphere.
TEST(FieldScene, CoincidentObjectsGiveTheFirstOfThem) {
  Scene scene = turned_boxes(40);
  std::set<ObjectId> first;
  for (const Instance& object : std::vector<Instance>(scene.instances().begin(), scene.instances().end())) {
    if (scene.meshes[object.mesh].occluder == MeshOccluder::exact) continue;
    first.insert(object.id);
    scene.add_instance(object.mesh, object.transform);
  }
  ASSERT_GT(first.size(), 30u);
  const TriangleSet set = flatten(scene);
  const field::ObjectFieldConfig config{.positions = 290, .directions = 16};
  const FieldScene tree = FieldScene::build(scene, config, {}, "", field::FieldMeshes::all, field::ObjectCull::tree);
  const FieldScene each = FieldScene::build(scene, config, {}, "", field::FieldMeshes::all, field::ObjectCull::each);
  ASSERT_TRUE(tree.uses_tree());
  // From 100 scene sizes away, towards points near the objects' centres.
  std::vector<Ray> rays;
  Rng rng(21);
  const std::vector<Bounds3f> boxes = tree.object_boxes();
  const float size = length(set.bounds.extent());
  for (int k = 0; k < 20000; ++k) {
    const Bounds3f& box = boxes[rng.next_u32() % boxes.size()];
    const Vec3f to = box.center() + Vec3f{rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f} * (0.5f * box.extent().x);
    const Vec3f from = to + uniform_sphere(rng.uniform(), rng.uniform()) * (100.0f * size);
    rays.push_back(Ray{from, to - from, 0.0f, 2.0f});
  }
  std::vector<Hit> hits_tree(rays.size()), hits_each(rays.size());
  field::intersect_batch(tree, rays, hits_tree);
  field::intersect_batch(each, rays, hits_each);
  std::size_t field_hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    for (const Hit& h : {hits_tree[i], hits_each[i], tree.intersect(rays[i]), each.intersect(rays[i])}) {
      if (!h.found || h.has_triangle()) continue;
      field_hits += h.instance == hits_each[i].instance ? 1 : 0;
      ASSERT_TRUE(first.count(h.instance)) << "ray " << i << ": object " << h.instance << ", the second of two in one place";
    }
  }
  EXPECT_GT(field_hits, rays.size() / 5);  // 4 answers a ray
}

// The batch queries run in parallel over blocks (the ThreadSanitizer step runs this test): the
// answers do not depend on the thread count.
TEST(FieldScene, BatchAnswersDoNotDependOnTheThreadCount) {
  const Scene scene = make_builtin_scene("boxes", {.size = 16});
  const TriangleSet set = flatten(scene);
  const FieldScene fields = FieldScene::build(scene, {.positions = 290, .directions = 16, .normals = field::NormalStorage::oct16});
  std::vector<Ray> rays = surface_origin_rays(set, 12, 30000);
  for (Ray& ray : rays) ray.tmin = 1e-4f * length(set.bounds.extent());
  std::vector<std::uint8_t> occluded[2];
  std::vector<Hit> hits[2];
  for (const int threads : {1, 2}) {
    ThreadLimit limit(threads);
    occluded[threads - 1].resize(rays.size());
    hits[threads - 1].resize(rays.size());
    field::occluded_batch(fields, rays, occluded[threads - 1]);
    field::intersect_batch(fields, rays, hits[threads - 1]);
  }
  EXPECT_EQ(occluded[0], occluded[1]);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) differ += hits[0][i].found != hits[1][i].found || hits[0][i].t != hits[1][i].t ? 1 : 0;
  EXPECT_EQ(differ, 0u);
}

// Occlusion only through single rays: what render_ao did before it traced a tile's AO rays as a batch.
struct RayByRay {
  const FieldScene& fields;
  bool occluded(const Ray& ray) const { return fields.occluded(ray); }
  const AccelStats& stats() const { return fields.stats(); }
  static std::string name() { return "ray by ray"; }
  static constexpr Exactness exactness = Exactness::approximate;
};

// A render's AO rays go through the fields' batch kernel (occluded_block) and give the same image,
// bit for bit, as tracing them one at a time, with random directions and along the line set.
TEST(FieldScene, RendersTheSameImageThroughTheBatchAsRayByRay) {
  const Scene scene = make_builtin_scene("cornell", {.size = 800});
  const Bvh bvh = Bvh::build(flatten(scene));
  const FieldScene fields = FieldScene::build(scene, {.positions = 1090, .directions = 16});
  const Camera camera = scene.camera_or_default(40, 30);
  for (const int psf_level : {0, 3}) {
    AoOptions options;
    options.spp = 2;
    options.ao_rays = 24;
    options.psf_level = psf_level;
    options.progress = false;
    const Image batched = render_ao(bvh, fields, scene, camera, options);
    const Image single = render_ao(bvh, RayByRay{fields}, scene, camera, options);
    ASSERT_EQ(batched.pixels.size(), single.pixels.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < batched.pixels.size(); ++i) differ += batched.pixels[i] == single.pixels[i] ? 0 : 1;
    EXPECT_EQ(differ, 0u) << "psf level " << psf_level;
    EXPECT_GT(compare_images(batched, render_ao(bvh, bvh, scene, camera, options)).rms, 0.0);  // the fields did answer
  }
}

// meshes=marked keeps every mesh exact but those a scene marks "field"; a mesh's own table
// parameters (scene JSON "field": {...}) override the structure's.
TEST(FieldScene, MarkedMeshesAndTheirOwnParameters) {
  Scene scene = make_builtin_scene("cornell", {.size = 500});
  std::uint32_t marked = 0;
  for (std::uint32_t m = 0; m < scene.meshes.size(); ++m)
    if (scene.meshes[m].occluder != MeshOccluder::exact) {
      marked = m;
      break;
    }
  scene.meshes[marked].occluder = MeshOccluder::field;
  scene.meshes[marked].field_params = "positions=1090,directions=16";
  const FieldScene all = FieldScene::build(scene, {.positions = 290, .directions = 8});
  const FieldScene only = FieldScene::build(scene, {.positions = 290, .directions = 8}, {}, "", field::FieldMeshes::marked);
  std::size_t fields_all = 0, fields_only = 0;
  for (std::uint32_t m = 0; m < scene.meshes.size(); ++m) {
    fields_all += all.mesh_field(m) != nullptr;
    fields_only += only.mesh_field(m) != nullptr;
  }
  EXPECT_GT(fields_all, 1u);
  EXPECT_EQ(fields_only, 1u);
  ASSERT_NE(only.mesh_field(marked), nullptr);
  EXPECT_EQ(only.mesh_field(marked)->config().positions, 1090);
  EXPECT_EQ(only.mesh_field(marked)->config().directions, 16);
  scene.meshes[marked].field_params = "directions=5";
  try {
    FieldScene::build(scene, {});
    ADD_FAILURE() << "a bad mesh parameter was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mesh " + scene.meshes[marked].name), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vf::test
