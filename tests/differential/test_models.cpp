// Every exact structure of the registry against the oracle on the shared real meshes: 100k rays per
// model, one test per model and structure, and the instance layer on rotated, scaled copies of real
// meshes. The oracle's answers are computed once per scene and ray set (oracle_cache.hpp).

#include <filesystem>
#include <memory>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "differential/harness.hpp"
#include "differential/oracle_cache.hpp"
#include "support/models.hpp"
#include "differential/ray_sets.hpp"
#include "differential/structure_specs.hpp"
#include "differential/test_scenes.hpp"
#include "support/test_scale.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf::test {
namespace {

constexpr std::size_t kRaysPerModel = 100'000;  // scaled down under sanitizers (test_scale.hpp)

std::filesystem::path model_path(const char* file) { return models_dir() / file; }

/// Every exact structure but brute force behind the instance layer, which is the oracle's O(N) a ray
/// again (on soups and copies the instance layer over it is tested by test_soups).
std::vector<std::string> model_specs() {
  std::vector<std::string> specs;
  for (const std::string& spec : exact_structure_specs())
    if (!spec.starts_with("brute")) specs.push_back(spec);
  return specs;
}

/// One model and one structure: a test each, so that ctest spreads them over its jobs, the oracle's
/// answers for the model computed once (oracle_cache.hpp) and shared by every structure's process.
class ModelVsOracle : public ::testing::TestWithParam<std::tuple<const char*, std::string>> {};

TEST_P(ModelVsOracle, AgreesOn100kRays) {
  const auto& [model, spec] = GetParam();
  const std::filesystem::path path = model_path(model);
  VF_SKIP_WITHOUT_MODELS(std::filesystem::exists(path), model);
  const Scene scene = load_scene(path.string());
  SceneGeometry geometry(scene);
  const TriangleSet& set = geometry.flattened();
  ASSERT_GT(set.size(), 0u);
  const std::vector<Ray> rays = model_rays(set, 2024, scaled_count(kRaysPerModel));
  const OracleAnswers answers = cached_oracle_answers(BruteForce::build(set), scene_hash(scene, set), rays, false);
  // One identity object: the instance layer's answers are the flattened oracle's, bit for bit.
  const BuiltStructure built = build_structure(test_sized(spec), geometry);
  const DiffReport r = compare_built(built, rays, answers, {.label = model});
  EXPECT_GT(r.oracle_hits, r.rays / 10) << model;
  EXPECT_EQ(r.closest_mismatches, 0u) << spec << " on " << model;
  EXPECT_EQ(r.occluded_mismatches, 0u) << spec << " on " << model;
}

INSTANTIATE_TEST_SUITE_P(SharedModels, ModelVsOracle,
                         ::testing::Combine(::testing::Values("bun_zipper.ply", "cow.obj", "igea-triangles.ply", "Armadillo.ply",
                                                              "dragon_vrip_res2.ply", "teapot.obj", "lucy.ply",
                                                              "CornellBox-Original.obj", "sponza.obj", "conference.obj"),
                                            ::testing::ValuesIn(model_specs())),
                         [](const auto& info) {
                           return spec_test_name(std::get<0>(info.param)) + "_" + spec_test_name(std::get<1>(info.param));
                         });

/// 16 rotated, scaled, overlapping copies each of the cow and the teapot, with both oracles' answers
/// on 20k rays, computed once for every structure.
struct CopiesOfRealMeshes {
  Scene scene;
  std::vector<Ray> rays;
  OracleAnswers flattened, instanced;

  static const CopiesOfRealMeshes* get() {
    static const std::unique_ptr<CopiesOfRealMeshes> data = [] {
      const std::filesystem::path cow = model_path("cow.obj"), teapot = model_path("teapot.obj");
      if (!std::filesystem::exists(cow) || !std::filesystem::exists(teapot)) return std::unique_ptr<CopiesOfRealMeshes>();
      auto d = std::make_unique<CopiesOfRealMeshes>();
      d->scene = scattered_copies({load_scene(cow.string()).meshes[0], load_scene(teapot.string()).meshes[0]}, 16, 2.0f, 5);
      const TriangleSet set = flatten(d->scene);
      d->rays = model_rays(set, 77, scaled_count(20'000));
      const std::uint64_t id = scene_hash(d->scene, set);
      d->flattened = cached_oracle_answers(BruteForce::build(set), id, d->rays, true);
      d->instanced = cached_oracle_answers(InstancedOracle(d->scene), id, d->rays, true);
      return d;
    }();
    return data.get();
  }
};

class InstancedModelVsOracle : public ::testing::TestWithParam<std::string> {};

// The instance layer against the instanced oracle (exact), the flattened structures against
// BruteForce over the world-space triangles.
TEST_P(InstancedModelVsOracle, CopiesOfRealMeshes) {
  const CopiesOfRealMeshes* data = CopiesOfRealMeshes::get();
  VF_SKIP_WITHOUT_MODELS(data != nullptr, "cow.obj or teapot.obj");
  SceneGeometry geometry(data->scene);
  const BuiltStructure built = build_structure(test_sized(GetParam()), geometry);
  const OracleAnswers& answers = is_two_level(built) ? data->instanced : data->flattened;
  const DiffReport r = compare_built(built, data->rays, answers, {.label = "cows and teapots"});
  EXPECT_GT(r.oracle_hits, r.rays / 10);
  EXPECT_EQ(r.closest_mismatches, 0u) << GetParam();
  EXPECT_EQ(r.occluded_mismatches, 0u) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Registry, InstancedModelVsOracle, ::testing::ValuesIn(exact_structure_specs()),
                         [](const auto& info) { return spec_test_name(info.param); });

}  // namespace
}  // namespace vf::test
