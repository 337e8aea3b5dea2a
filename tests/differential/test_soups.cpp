// Every exact structure of the registry, flattened and as an instance layer, against the oracle on
// procedural scenes and adversarial rays.

#include <cstdio>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "differential/harness.hpp"
#include "differential/oracle_cache.hpp"
#include "differential/ray_sets.hpp"
#include "differential/structure_specs.hpp"
#include "differential/test_scenes.hpp"
#include "support/test_scale.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::test {
namespace {

/// A named set of rays.
struct RaySet {
  std::string name;
  std::vector<Ray> rays;
};

/// Rays per set: `n`, or under the sanitizer run (VISFIELD_TEST_SCALE) a fraction of it for scenes of
/// 10,000 triangles or more, where the brute-force oracle dominates the time (40-120 s per structure
/// under ASan at full count). Small scenes keep every ray: a soup of two triangles needs them to be
/// hit at all.
std::size_t rays_for(const TriangleSet& set, std::size_t n) { return set.size() >= 10000 ? scaled_count(n) : n; }

/// The ray sets every scene is checked with (15k rays, plus the boundary-t copies of their hits).
std::vector<RaySet> adversarial_rays(const TriangleSet& set, std::uint64_t seed) {
  return {{"random", random_rays(set, seed, rays_for(set, 4000))},
          {"axis-parallel", axis_parallel_rays(set, seed, rays_for(set, 2000))},
          {"zero-component", zero_component_rays(set, seed, rays_for(set, 2000))},
          {"surface-origin", surface_origin_rays(set, seed, rays_for(set, 2000))},
          {"grazing", grazing_rays(set, seed, rays_for(set, 2000))},
          {"behind-origin", behind_origin_rays(set, seed, rays_for(set, 1000))},
          {"denormal", denormal_rays(set, seed, rays_for(set, 1000))},
          {"tiny-direction", tiny_direction_rays(set, seed, rays_for(set, 1000))}};
}

class ExactVsOracle : public ::testing::TestWithParam<std::string> {
 protected:
  /// Builds GetParam() over `scene` and checks it against its oracle (BruteForce over the flattened
  /// triangles, or InstancedOracle for the instance layer) with the adversarial rays and the
  /// boundary-t copies of every hit ray; asserts zero mismatches.
  void check(const std::string& name, const Scene& scene, std::uint64_t seed = 1) {
    SceneGeometry geometry(scene);
    const TriangleSet& set = geometry.flattened();
    ASSERT_GT(set.size(), 0u);
    const BuiltStructure built = build_structure(test_sized(GetParam()), geometry);
    const std::uint64_t id = scene_hash(scene, set);
    if (is_two_level(built)) {
      check_against(InstancedOracle(scene), id, built, name, set, seed);
    } else {
      check_against(BruteForce::build(set), id, built, name, set, seed);
    }
  }

  /// The oracle's answers come from the cache (oracle_cache.hpp): every structure's test process
  /// compares against the answers the first one computed for the scene and rays.
  template <class Oracle>
  void check_against(const Oracle& oracle, std::uint64_t scene_id, const BuiltStructure& built, const std::string& scene,
                     const TriangleSet& set, std::uint64_t seed) {
    for (const RaySet& ray_set : adversarial_rays(set, seed)) {
      const std::string label = scene + ", " + ray_set.name + " rays";
      const OracleAnswers answers = cached_oracle_answers(oracle, scene_id, ray_set.rays, true);
      const DiffReport main = compare_built(built, ray_set.rays, answers, {.label = label});
      EXPECT_EQ(main.closest_mismatches, 0u) << label;
      EXPECT_EQ(main.occluded_mismatches, 0u) << label;
      // Every ray set reaches the geometry (rays in a triangle's plane, or at a corner a denormal
      // off its planes, may all miss it).
      if (ray_set.name != "grazing" && ray_set.name != "denormal") {
        EXPECT_GT(main.oracle_hits, 0u) << label << ": no ray hits anything";
      }

      // The same rays with tmin or tmax exactly at each hit and just below it: the range (tmin, tmax]
      // keeps a hit at tmax and one just above tmin, and drops one at tmin.
      const std::vector<Ray> boundary = boundary_t_rays(ray_set.rays, answers.closest);
      const OracleAnswers boundary_answers = cached_oracle_answers(oracle, scene_id, boundary, true);
      for (std::size_t i = 0; i < boundary.size(); i += 4) {
        const float t = boundary[i].tmax;
        ASSERT_TRUE(boundary_answers.closest[i]) << label << ": tmax = t must hit";
        ASSERT_TRUE(!boundary_answers.closest[i + 1] || boundary_answers.closest[i + 1].t > t)
            << label << ": tmin = t must not hit at t";
        ASSERT_TRUE(boundary_answers.closest[i + 3]) << label << ": tmin just below t must hit";
        ASSERT_LE(boundary_answers.closest[i + 3].t, t) << label;
      }
      const DiffReport edge = compare_built(built, boundary, boundary_answers, {.label = label + ", boundary t"});
      EXPECT_EQ(edge.closest_mismatches, 0u) << label;
      EXPECT_EQ(edge.occluded_mismatches, 0u) << label;
      hits_by_set_[ray_set.name] += main.oracle_hits;
      rays_by_set_[ray_set.name] += main.rays;
    }
  }

  // Over a test's scenes, each ray set must hit often, or the comparison says little.
  void TearDown() override {
    for (const auto& [name, hits] : hits_by_set_) {
      std::printf("  %s rays: %zu of %zu hit\n", name.c_str(), hits, rays_by_set_[name]);
      if (name != "grazing" && name != "denormal") {
        EXPECT_GT(hits, rays_by_set_[name] / 50) << name << " rays rarely hit";
      }
    }
  }

  std::map<std::string, std::size_t> hits_by_set_, rays_by_set_;
};

TEST_P(ExactVsOracle, RandomSoupsOfSeveralSizesAndSeeds) {
  for (std::uint64_t seed : {1u, 2u, 3u})
    for (std::size_t n : {2u, 17u, 300u, 5000u})
      check("soup n=" + std::to_string(n) + " seed=" + std::to_string(seed),
            scene_from_triangles(random_soup(seed, n, 0.01f, 0.1f)), seed);
}

TEST_P(ExactVsOracle, TinyAndHugeTrianglesMixed) {
  check("tiny+huge", scene_from_triangles(random_soup(7, 20000, 1e-5f, 3.0f)), 7);
}

TEST_P(ExactVsOracle, SingleTriangle) {
  check("one triangle", scene_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}}));
  check("one tilted triangle", scene_from_triangles({{Vec3f{0.1f, -2, 3}, Vec3f{1, 0.3f, 0}, Vec3f{0, 1, 0.7f}}}));
}

TEST_P(ExactVsOracle, CoplanarTriangles) {
  check("coplanar z=0.5", scene_from_triangles(coplanar_soup(3, 2000, {0, 0, 0.5f}, {1, 0, 0}, {0, 1, 0})));
  check("coplanar tilted",
        scene_from_triangles(coplanar_soup(4, 2000, {0.1f, 0.2f, 0.3f}, {0.8f, 0.6f, 0.0f}, {-0.36f, 0.48f, 0.8f})));
}

TEST_P(ExactVsOracle, DuplicateTrianglesTie) {
  std::vector<Triangle> triangles = random_soup(5, 200, 0.05f, 0.2f);
  const Triangle repeated{Vec3f{0.2f, 0.2f, 0.5f}, Vec3f{0.8f, 0.3f, 0.5f}, Vec3f{0.4f, 0.9f, 0.6f}};
  for (int i = 0; i < 60; ++i) triangles.insert(triangles.begin() + 3 * i, repeated);
  check("duplicates", scene_from_triangles(triangles));
  check("only duplicates", scene_from_triangles(std::vector<Triangle>(500, repeated)));
}

TEST_P(ExactVsOracle, SharedEdgeHeightField) { check("height field", scene_from_triangles(height_field(9, 64))); }

TEST_P(ExactVsOracle, BuiltinScenes) {
  for (const char* name : {"sphere", "boxes", "stadium", "cornell"})
    check(std::string("builtin ") + name, make_builtin_scene(name, {.seed = 3, .size = 0}));
}

TEST_P(ExactVsOracle, RotatedScaledOverlappingCopies) {
  check("scattered copies",
        scattered_copies({mesh_from_triangles(height_field(4, 12)), mesh_from_triangles(random_soup(6, 300, 0.02f, 0.1f))},
                         25, 1.5f, 11),
        11);
}

TEST_P(ExactVsOracle, CopiesAtTheSamePlaceTie) {
  // Identical objects: every hit is a tie between them, won by the lowest id.
  Scene scene = scene_from_triangles(random_soup(8, 400, 0.02f, 0.1f));
  for (int i = 0; i < 5; ++i) scene.add_instance(0, Transform{});
  check("coincident copies", scene, 8);
}

INSTANTIATE_TEST_SUITE_P(Registry, ExactVsOracle, ::testing::ValuesIn(exact_structure_specs()),
                         [](const auto& info) { return spec_test_name(info.param); });

}  // namespace
}  // namespace vf::test
