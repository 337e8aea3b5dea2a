#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "synthetic.hpp"
#include "visfield/core/error.hpp"
#include "visfield/select/critical_rays.hpp"

namespace vf {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(CriticalRays, EstimateIsTreeBuildOverPerRayGainWithEpsilon) {
  // T_B^H = 12 ms, t^G = 5 us, t^H = 4.1 us, eps = 0.01: 12000 us / (5.05 - 4.1) us.
  EXPECT_DOUBLE_EQ(estimated_critical_rays(12.0, 5.0, 4.1, 0.01), 12000.0 / (5.0 * 1.01 - 4.1));
  // Without epsilon: 50 ms / (3 - 1) us = 25000 rays.
  EXPECT_DOUBLE_EQ(estimated_critical_rays(50.0, 3.0, 1.0, 0.0), 25000.0);
}

TEST(CriticalRays, EstimateIsInfiniteWhenTheGridIsNeverSlowerPerRay) {
  EXPECT_EQ(estimated_critical_rays(10.0, 1.0, 2.0, 0.01), kInf);
  // Step 5: equal per-ray times keep the grid, whatever epsilon would make of the denominator.
  EXPECT_EQ(estimated_critical_rays(10.0, 1.0, 1.0, 0.01), kInf);
  EXPECT_EQ(estimated_critical_rays(10.0, 1.0, 1.0, 0.0), kInf);
  EXPECT_EQ(estimated_critical_rays(10.0, 0.0, 0.0, 0.01), kInf);
  // Just above the tie, epsilon bounds the count: 10000 us / (1.0001 * 1.01 - 1) us, not 10000 / 0.0001.
  EXPECT_NEAR(estimated_critical_rays(10.0, 1.0001, 1.0, 0.01), 10000.0 / (1.0001 * 1.01 - 1.0), 1e-6);
}

TEST(CriticalRays, ExactIsWhereTheTotalsMeet) {
  // The paper's row "building": T_B^G 21, T_B^H 995 ms, t^G 6.3, t^H 3.1 us -> 304,375 (Table 1: 304,414).
  const double rc = exact_critical_rays(21.0, 995.0, 6.3, 3.1);
  EXPECT_NEAR(rc, 974000.0 / 3.2, 1e-6);
  EXPECT_NEAR(21.0 + rc * 6.3e-3, 995.0 + rc * 3.1e-3, 1e-9);
  EXPECT_EQ(exact_critical_rays(2.0, 12.0, 4.0, 4.0), kInf);  // same per-ray time: the grid never loses
  EXPECT_EQ(exact_critical_rays(2.0, 12.0, 3.0, 4.0), kInf);
  EXPECT_EQ(exact_critical_rays(20.0, 12.0, 5.0, 4.0), 0.0);  // the tree is cheaper to build and faster
}

TEST(CriticalRays, ExactFromMeasurementUsesTheFullTimingsOfTheKind) {
  SceneMeasurement m = test::model_scene("s", 1024, 1e-3, 0.1, 0.2, 1.0, 3.0, 0.5);
  m.rays[calibrated_kind_index(RayKind::random)].grid_sample_us = 100.0;  // must not be used
  const double tree_random = 0.1 * 10.0, tree_build = 1e-3 * 1024 * 10.0;
  EXPECT_DOUBLE_EQ(exact_critical_rays(m, RayKind::random), (tree_build - 1.0) * 1000.0 / (3.0 - tree_random));
  EXPECT_EQ(exact_critical_rays(m, RayKind::path), kInf);  // grid 0.5 us < tree 2 us
}

TEST(CriticalRays, DecisionFlipsAtTheCriticalCount) {
  const double rc = estimated_critical_rays(50.0, 3.0, 1.0, 0.0);  // 25000
  EXPECT_TRUE(grid_wins(0.0, rc));
  EXPECT_TRUE(grid_wins(24999.0, rc));
  EXPECT_FALSE(grid_wins(25000.0, rc));
  EXPECT_FALSE(grid_wins(25001.0, rc));
  EXPECT_TRUE(grid_wins(1e300, kInf));
  EXPECT_FALSE(grid_wins(0.0, 0.0));
}

TEST(CriticalRays, CostModelEstimatesFollowEquations7And8) {
  CalibrationConstants c;
  c.build_ms_per_n_log2_n = 2e-4;
  c.ray_us_per_log2_n = {0.05, 0.125};
  EXPECT_DOUBLE_EQ(estimated_tree_build_ms(c, 4096), 2e-4 * 4096 * 12);
  EXPECT_DOUBLE_EQ(estimated_tree_ray_us(c, RayKind::random, 4096), 0.05 * 12);
  EXPECT_DOUBLE_EQ(estimated_tree_ray_us(c, RayKind::path, 4096), 0.125 * 12);
  // A one-triangle scene is costed like two: log2 N never 0.
  EXPECT_DOUBLE_EQ(estimated_tree_ray_us(c, RayKind::path, 1), 0.125);
  EXPECT_DOUBLE_EQ(estimated_critical_rays(c, RayKind::path, 4096, 2.0, 0.01),
                   2e-4 * 4096 * 12 * 1000.0 / (2.0 * 1.01 - 0.125 * 12));
}

TEST(CriticalRays, ErrorPercentIsRelativeAndUndefinedForInfiniteValues) {
  EXPECT_DOUBLE_EQ(estimate_error_percent(125.0, 100.0), 25.0);
  EXPECT_DOUBLE_EQ(estimate_error_percent(75.0, 100.0), -25.0);
  EXPECT_TRUE(std::isnan(estimate_error_percent(kInf, 100.0)));
  EXPECT_TRUE(std::isnan(estimate_error_percent(100.0, kInf)));
  EXPECT_TRUE(std::isnan(estimate_error_percent(100.0, 0.0)));
}

TEST(Constants, AreTheMeansOfEquations7And8) {
  std::vector<SceneMeasurement> scenes;
  SceneMeasurement a, b;
  a.triangles = 256;   // log2 = 8
  a.tree_build_ms = 4.096;
  a.rays[0].tree_us = 0.8;
  a.rays[1].tree_us = 1.6;
  b.triangles = 1024;  // log2 = 10
  b.tree_build_ms = 30.72;
  b.rays[0].tree_us = 3.0;
  b.rays[1].tree_us = 0.5;
  scenes = {a, b};
  const CalibrationConstants c = compute_constants(scenes);
  EXPECT_DOUBLE_EQ(c.build_ms_per_n_log2_n, 0.5 * (4.096 / (256 * 8) + 30.72 / (1024 * 10)));
  EXPECT_DOUBLE_EQ(c.ray_us(RayKind::random), 0.5 * (0.8 / 8 + 3.0 / 10));
  EXPECT_DOUBLE_EQ(c.ray_us(RayKind::path), 0.5 * (1.6 / 8 + 0.5 / 10));
  const std::vector<std::size_t> only_b{1};
  const CalibrationConstants cb = compute_constants(scenes, only_b);
  EXPECT_DOUBLE_EQ(cb.build_ms_per_n_log2_n, 30.72 / (1024 * 10));
  EXPECT_DOUBLE_EQ(cb.ray_us(RayKind::random), 0.3);
}

TEST(Constants, ModelScenesGiveBackTheirConstants) {
  std::vector<SceneMeasurement> scenes;
  for (std::uint64_t n : {100u, 5000u, 300000u}) scenes.push_back(test::model_scene("s", n, 3e-4, 0.07, 0.11, 1.0, 2.0, 2.0));
  const CalibrationConstants c = compute_constants(scenes);
  EXPECT_NEAR(c.build_ms_per_n_log2_n, 3e-4, 1e-15);
  EXPECT_NEAR(c.ray_us(RayKind::random), 0.07, 1e-15);
  EXPECT_NEAR(c.ray_us(RayKind::path), 0.11, 1e-15);
}

TEST(Constants, RefuseAnEmptyOrOutOfRangeSubset) {
  std::vector<SceneMeasurement> scenes{test::model_scene("s", 100, 1e-4, 0.1, 0.1, 1, 1, 1)};
  EXPECT_THROW(compute_constants(std::span<const SceneMeasurement>()), Error);
  const std::vector<std::size_t> bad{3};
  EXPECT_THROW(compute_constants(scenes, bad), Error);
}

}  // namespace
}  // namespace vf
