// Grid queries against the BruteForce oracle: random soups, adversarial rays, hits on cell
// boundaries, t ranges ending at hits, flat and far-away scenes, real models.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "support/models.hpp"
#include "support/test_scale.hpp"
#include "unit/grid/grid_test_support.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

using test::set_from_triangles;
using test::Triangle;

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Random, axis-parallel, zero-component, surface-origin, grazing and model-style rays, and the
/// copies of every hit ray whose t range starts or ends exactly at (or one ulp beside) the hit.
std::vector<Ray> adversarial_rays(const TriangleSet& set, std::uint64_t seed, std::size_t per_kind) {
  std::vector<Ray> rays;
  const auto append = [&](const std::vector<Ray>& more) { rays.insert(rays.end(), more.begin(), more.end()); };
  append(test::random_rays(set, seed, per_kind));
  append(test::axis_parallel_rays(set, seed, per_kind));
  append(test::zero_component_rays(set, seed, per_kind));
  append(test::surface_origin_rays(set, seed, per_kind));
  append(test::grazing_rays(set, seed, per_kind));
  append(test::model_rays(set, seed, per_kind));
  const BruteForce oracle = BruteForce::build(set);
  std::vector<Hit> hits;
  for (const Ray& r : rays) hits.push_back(oracle.intersect(r));
  append(test::boundary_t_rays(rays, hits));
  return rays;
}

/// Builds a grid over `set` and checks it against the oracle on the adversarial rays.
void check_scene(const TriangleSet& set, const std::string& label, std::uint64_t seed = 1, std::size_t per_kind = 400,
                 const UniformGridConfig& config = {}) {
  const UniformGrid grid = UniformGrid::build(set, config);
  const std::vector<Ray> rays = adversarial_rays(set, seed, per_kind);
  const std::size_t hits = test::expect_same_as_oracle(grid, set, rays, label);
  EXPECT_GT(hits, rays.size() / 10) << label << ": the rays should hit something";
}

TEST(GridQueries, RandomSoupsOfSeveralSizesAndSeeds) {
  for (std::uint64_t seed : {1u, 2u, 3u})
    for (std::size_t n : {1u, 7u, 300u, 4000u})
      check_scene(set_from_triangles(test::random_soup(seed, n, 0.01f, 0.1f)),
                  "soup n=" + std::to_string(n) + " seed=" + std::to_string(seed), seed);
}

TEST(GridQueries, TinyHugeAndMixedTriangles) {
  check_scene(set_from_triangles(test::random_soup(4, 3000, 1e-5f, 1e-3f)), "tiny", 4);
  check_scene(set_from_triangles(test::random_soup(5, 200, 0.5f, 3.0f)), "huge", 5);
  check_scene(set_from_triangles(test::random_soup(6, 5000, 1e-5f, 3.0f)), "mixed", 6);
}

TEST(GridQueries, EveryDensityAndBothOverlapModes) {
  const TriangleSet set = set_from_triangles(test::random_soup(7, 2000, 0.005f, 0.3f));
  for (float density : {0.1f, 1.0f, 8.0f, 64.0f})
    for (bool exact : {true, false})
      check_scene(set, "density " + std::to_string(density) + (exact ? " exact" : " boxes"), 7, 200,
                  {.density = density, .exact_overlap = exact});
}

TEST(GridQueries, DuplicateTrianglesTieTowardTheLowestIndex) {
  std::vector<Triangle> triangles = test::random_soup(8, 1000, 0.01f, 0.2f);
  for (int i = 1; i < 20; ++i) triangles[static_cast<std::size_t>(45 * i)] = triangles[3];
  check_scene(set_from_triangles(triangles), "duplicates", 8);
}

TEST(GridQueries, RaysStartingInsideTheGrid) {
  const TriangleSet set = set_from_triangles(test::random_soup(9, 3000, 0.01f, 0.1f));
  Rng rng(9, 2);
  std::vector<Ray> rays;
  for (int i = 0; i < 3000; ++i) {
    const Ray r{test::point_around(rng, set.bounds, 0.0f), test::random_direction(rng)};
    rays.push_back(r);
    rays.push_back(Ray{r.org, r.dir, 0.0f, 0.05f * rng.uniform()});  // short segments ending inside
  }
  test::expect_same_as_oracle(UniformGrid::build(set), set, rays, "inside");
}

/// Triangles lying in cell-boundary planes of unit_cells(4) (x = 1, y = 2, z = 3) and in the box
/// faces (z = 0, x = 4), and triangles whose edges run along cell edges.
std::vector<Triangle> boundary_scene() {
  return {
      {Vec3f{1, 0.5f, 0.5f}, Vec3f{1, 3.5f, 0.5f}, Vec3f{1, 0.5f, 3.5f}},  // plane x = 1
      {Vec3f{0.5f, 2, 0.5f}, Vec3f{3.5f, 2, 0.5f}, Vec3f{3.5f, 2, 3.5f}},  // plane y = 2
      {Vec3f{0, 0, 3}, Vec3f{4, 0, 3}, Vec3f{0, 4, 3}},                    // plane z = 3, edges on cell edges
      {Vec3f{4, 4, 3}, Vec3f{0, 4, 3}, Vec3f{4, 0, 3}},                    // its mate: the square z = 3
      {Vec3f{0, 0, 0}, Vec3f{4, 0, 0}, Vec3f{4, 4, 0}},                    // box face z = 0
      {Vec3f{4, 1, 1}, Vec3f{4, 3, 1}, Vec3f{4, 2, 3}},                    // box face x = 4
      {Vec3f{2, 2, 2}, Vec3f{3, 2, 2}, Vec3f{2, 3, 2}},                    // corner on the point (2, 2, 2)
  };
}

TEST(GridQueries, HitsOnCellBoundaryPlanesAreNeverMissed) {
  const TriangleSet set = set_from_triangles(boundary_scene());
  const UniformGrid grid = UniformGrid::build(set, test::unit_cells(4));
  ASSERT_EQ(grid.geometry().plane(0, 1), 1.0);

  // Perpendicular rays onto each plane, at cell-interior and cell-edge positions.
  const auto hit_t = [&](Ray r) {
    const Hit h = grid.intersect(r);
    return h ? h.t : -1.0f;
  };
  EXPECT_EQ(hit_t(Ray{{-1, 1.5f, 1.5f}, {1, 0, 0}}), 2.0f);   // plane x = 1
  EXPECT_EQ(hit_t(Ray{{-1, 1.0f, 1.0f}, {1, 0, 0}}), 2.0f);   // ... along the cell edge y = z = 1
  EXPECT_EQ(hit_t(Ray{{2.5f, 5, 1.5f}, {0, -1, 0}}), 3.0f);   // plane y = 2 from above
  EXPECT_EQ(hit_t(Ray{{3, 5, 3}, {0, -1, 0}}), 3.0f);         // ... through the cell corner line x = 3, z = 3
  EXPECT_EQ(hit_t(Ray{{1.5f, 1.5f, 5}, {0, 0, -1}}), 2.0f);   // plane z = 3 from above
  EXPECT_EQ(hit_t(Ray{{2, 2, 5}, {0, 0, -1}}), 2.0f);         // ... exactly through cell corners (2, 2, z)
  EXPECT_EQ(hit_t(Ray{{3, 1, 5}, {0, 0, -1}}), 2.0f);         // ... on the diagonal shared by the two triangles
  EXPECT_EQ(hit_t(Ray{{2.25f, 2.25f, 2.5f}, {0, 0, -1}}), 0.5f);  // corner triangle at z = 2
  EXPECT_EQ(hit_t(Ray{{2.5f, 0.5f, 2.5f}, {0, 0, -1}}), 2.5f);  // box face z = 0
  EXPECT_EQ(hit_t(Ray{{5, 2, 2}, {-1, 0, 0}}), 1.0f);          // box face x = 4

  // Oblique rays aimed at points on every triangle, including corners and edge points that lie on
  // cell edges, from inside and outside the box, and rays running inside the boundary planes.
  Rng rng(11, 3);
  std::vector<Ray> rays;
  for (const Triangle& t : set.triangles)
    for (int i = 0; i < 300; ++i) {
      const float u = std::floor(rng.uniform() * 5) / 4, v = std::floor(rng.uniform() * 5) / 4 * (1 - u);
      const Vec3f target = test::point_on(t, u, v);
      const Vec3f org = test::point_around(rng, set.bounds, rng.uniform() < 0.5f ? 0.0f : 0.5f);
      rays.push_back(Ray{org, target - org});
      Vec3f in_plane = test::random_direction(rng);
      in_plane[static_cast<int>(rng.next_u32() % 3)] = 0.0f;
      Vec3f on_plane = org;
      on_plane[static_cast<int>(rng.next_u32() % 3)] = static_cast<float>(rng.next_u32() % 5);
      rays.push_back(Ray{on_plane, in_plane});
      rays.push_back(Ray{target, test::random_direction(rng)});  // origin on the triangle
    }
  const std::size_t hits = test::expect_same_as_oracle(grid, set, rays, "boundary planes");
  EXPECT_GT(hits, rays.size() / 3);

  // The same scene with the default (non-aligned) resolution.
  test::expect_same_as_oracle(UniformGrid::build(set), set, rays, "boundary scene, default grid");
}

TEST(GridQueries, TRangeEndingExactlyAtAHit) {
  const TriangleSet set = set_from_triangles(test::random_soup(12, 2000, 0.01f, 0.1f));
  const UniformGrid grid = UniformGrid::build(set);
  const BruteForce oracle = BruteForce::build(set);
  std::size_t checked = 0;
  for (const Ray& r : test::model_rays(set, 12, 2000)) {
    const Hit h = oracle.intersect(r);
    if (!h) continue;
    ++checked;
    const Ray to_hit{r.org, r.dir, r.tmin, h.t}, from_hit{r.org, r.dir, h.t, r.tmax};
    ASSERT_TRUE(grid.occluded(to_hit));
    ASSERT_TRUE(test::same_bits(grid.intersect(to_hit), h));
    ASSERT_TRUE(test::same_bits(grid.intersect(from_hit), oracle.intersect(from_hit)));  // (tmin, tmax]: not h
    const Ray short_of_hit{r.org, r.dir, r.tmin, std::nextafter(h.t, -kInf)};
    ASSERT_TRUE(test::same_bits(grid.intersect(short_of_hit), oracle.intersect(short_of_hit)));
    ASSERT_EQ(grid.occluded(short_of_hit), oracle.occluded(short_of_hit));
  }
  EXPECT_GT(checked, 500u);
}

TEST(GridQueries, FlatSceneInThePlaneZEqualsZero) {
  const TriangleSet set = set_from_triangles(test::coplanar_soup(13, 3000, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  check_scene(set, "flat z=0", 13);
  // Rays parallel to the plane, in it and just beside it, and perpendicular to it.
  Rng rng(13, 4);
  std::vector<Ray> rays;
  for (int i = 0; i < 2000; ++i) {
    Vec3f org = test::point_around(rng, set.bounds, 0.2f);
    const float offsets[] = {0.0f, 1e-6f, -1e-3f};
    org.z = offsets[i % 3];
    Vec3f dir = test::random_direction(rng);
    dir.z = 0.0f;
    rays.push_back(Ray{org, dir});
    rays.push_back(Ray{Vec3f{org.x, org.y, 1.0f}, Vec3f{0, 0, -1}});
    rays.push_back(Ray{Vec3f{org.x, org.y, -1.0f}, Vec3f{0.01f, 0, 1}});
  }
  test::expect_same_as_oracle(UniformGrid::build(set), set, rays, "flat z=0, parallel and perpendicular");
}

TEST(GridQueries, SingleTriangle) {
  const TriangleSet set = set_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}});
  const UniformGrid grid = UniformGrid::build(set);
  const Hit h = grid.intersect(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}});
  ASSERT_TRUE(h.found);
  EXPECT_EQ(h.t, 2.0f);
  EXPECT_EQ(h.u, 0.25f);
  EXPECT_EQ(h.v, 0.25f);
  EXPECT_EQ(h.prim, 0u);
  EXPECT_EQ(h.instance, 0u);
  EXPECT_FALSE(grid.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, 0.0f, 1.99f}));
  EXPECT_TRUE(grid.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, 0.0f, 2.0f}));
  EXPECT_FALSE(grid.intersect(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, 1}}).found);
  EXPECT_FALSE(grid.intersect(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, 0}}).found);  // no direction
  check_scene(set, "single triangle");
}

TEST(GridQueries, FarOriginsAndAFarAwayScene) {
  std::vector<Triangle> triangles = test::random_soup(14, 2000, 0.01f, 0.1f);
  for (Triangle& t : triangles)
    for (Vec3f& p : t) p = p * 10.0f + Vec3f{1000.0f, -500.0f, 2000.0f};
  const TriangleSet set = set_from_triangles(triangles);
  check_scene(set, "far from the world origin", 14);
  Rng rng(14, 5);
  std::vector<Ray> rays;
  for (int i = 0; i < 2000; ++i) {
    const Vec3f target = test::point_around(rng, set.bounds, 0.0f);
    const Vec3f org = target + test::random_direction(rng) * 1000.0f;
    rays.push_back(Ray{org, target - org});
  }
  const std::size_t hits = test::expect_same_as_oracle(UniformGrid::build(set), set, rays, "far origins");
  EXPECT_GT(hits, 500u);
}

TEST(GridQueries, BuiltinScenes) {
  for (const char* name : {"stadium", "boxes", "cornell", "sphere"}) {
    const TriangleSet set = flatten(make_builtin_scene(name, {.seed = 3, .size = 0}));
    // The brute-force oracle over the full-size scenes: a tenth of the rays under the sanitizers.
    check_scene(set, name, 15, std::max<std::size_t>(60, test::scaled_count(300)));
  }
}

TEST(GridQueries, SharedModels) {
  const std::filesystem::path models = test::models_dir();
  VF_SKIP_WITHOUT_MODELS(std::filesystem::exists(models), "the shared models folder");
  for (const char* file : {"CornellBox-Original.obj", "cow.obj", "sponza.obj"}) {
    const std::filesystem::path path = models / file;
    VF_SKIP_WITHOUT_MODELS(std::filesystem::exists(path), path.filename().string());
    const TriangleSet set = flatten(load_scene(path.string()));
    const UniformGrid grid = UniformGrid::build(set);
    const std::vector<Ray> rays = test::model_rays(set, 16, 3000);
    const std::size_t hits = test::expect_same_as_oracle(grid, set, rays, file);
    EXPECT_GT(hits, rays.size() / 4) << file;
  }
}

}  // namespace
}  // namespace vf
