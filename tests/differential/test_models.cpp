// Every exact structure against the oracle on the shared real meshes: 100k rays per model.

#include <filesystem>

#include <gtest/gtest.h>

#include "differential/exact_structures.hpp"
#include "differential/harness.hpp"
#include "differential/ray_sets.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf::test {
namespace {

constexpr std::size_t kRaysPerModel = 100'000;

class ModelVsOracle : public ::testing::TestWithParam<const char*> {};

TEST_P(ModelVsOracle, EveryExactStructureAgreesOn100kRays) {
  const std::filesystem::path path = std::filesystem::path(VISFIELD_MODELS_DIR) / GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
  const TriangleSet set = flatten(load_scene(path.string()));
  ASSERT_GT(set.size(), 0u);
  const std::vector<Ray> rays = model_rays(set, 2024, kRaysPerModel);
  const BruteForce oracle = BruteForce::build(set);
  const OracleAnswers answers = oracle_answers(oracle, rays, false);
  ExactStructures::for_each([&]<class Structure>() {
    const Structure accel = build_for_test<Structure>(set);
    const DiffReport r = compare_answers(accel, rays, answers, {.label = GetParam()});
    EXPECT_GT(r.oracle_hits, r.rays / 10) << GetParam();
    EXPECT_EQ(r.closest_mismatches, 0u) << Structure::name() << " on " << GetParam();
    EXPECT_EQ(r.occluded_mismatches, 0u) << Structure::name() << " on " << GetParam();
  });
}

INSTANTIATE_TEST_SUITE_P(SharedModels, ModelVsOracle,
                         ::testing::Values("bun_zipper.ply", "cow.obj", "igea-triangles.ply", "Armadillo.ply",
                                           "dragon_vrip_res2.ply", "teapot.obj", "lucy.ply",
                                           "CornellBox-Original.obj", "sponza.obj", "conference.obj"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace vf::test
