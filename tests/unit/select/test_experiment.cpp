#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "synthetic.hpp"
#include "visfield/core/error.hpp"
#include "visfield/select/experiment.hpp"

namespace vf {
namespace {

using test::model_scene;

// Four scenes that follow the cost model exactly (C_B = 1e-4 ms, C_R = 0.1 / 0.2 us) with free grid
// builds, so with epsilon = 0 every estimate equals the exact R_C. Exact R_C (random, path):
// a: 512, inf; b: 4915.2, 2457.6; c: inf, 10485.76; d: 20.48, 204.8.
std::vector<SceneMeasurement> model_scenes() {
  return {model_scene("a", 1024, 1e-4, 0.1, 0.2, 0.0, 3.0, 1.0), model_scene("b", 4096, 1e-4, 0.1, 0.2, 0.0, 2.2, 4.4),
          model_scene("c", 65536, 1e-4, 0.1, 0.2, 0.0, 1.6, 13.2), model_scene("d", 256, 1e-4, 0.1, 0.2, 0.0, 10.8, 2.6)};
}

TEST(LeaveOneOut, ModelScenesAreEstimatedExactly) {
  const auto scenes = model_scenes();
  const auto random = leave_one_out(scenes, RayKind::random, 0.0);
  ASSERT_EQ(random.size(), 4u);
  EXPECT_NEAR(random[0].exact, 512.0, 1e-9);
  EXPECT_NEAR(random[1].exact, 4915.2, 1e-9);
  EXPECT_TRUE(std::isinf(random[2].exact));
  EXPECT_NEAR(random[3].exact, 20.48, 1e-9);
  for (const auto& row : random) {
    if (std::isinf(row.exact)) {
      EXPECT_TRUE(std::isinf(row.estimate));
      EXPECT_TRUE(std::isnan(row.error_percent));
    } else {
      EXPECT_NEAR(row.estimate, row.exact, 1e-9 * row.exact);
      EXPECT_NEAR(row.error_percent, 0.0, 1e-9);
    }
  }
  const auto path = leave_one_out(scenes, RayKind::path, 0.0);
  EXPECT_TRUE(std::isinf(path[0].exact));
  EXPECT_NEAR(path[2].estimate, 10485.76, 1e-6);
}

TEST(LeaveOneOut, CalibratesOnTheOtherScenesOnly) {
  // Three scenes with different constants: the estimate of scene i uses the mean constants of the others.
  std::vector<SceneMeasurement> scenes{model_scene("p", 1024, 1e-4, 0.1, 0.1, 0.5, 5.0, 5.0),
                                       model_scene("q", 4096, 3e-4, 0.2, 0.2, 0.5, 5.0, 5.0),
                                       model_scene("r", 256, 2e-4, 0.3, 0.3, 0.5, 5.0, 5.0)};
  scenes[0].rays[0].grid_sample_us = 4.0;  // the estimate uses the sample, not the full timing
  const auto rows = leave_one_out(scenes, RayKind::random, 0.01);
  const double cb = 0.5 * (3e-4 + 2e-4), cr = 0.5 * (0.2 + 0.3);
  const double expected = cb * 1024 * 10 * 1000.0 / (4.0 * 1.01 - cr * 10);
  EXPECT_NEAR(rows[0].estimate, expected, 1e-9 * expected);
  const double exact = (1e-4 * 1024 * 10 - 0.5) * 1000.0 / (5.0 - 1.0);
  EXPECT_NEAR(rows[0].exact, exact, 1e-9 * exact);
  EXPECT_NEAR(rows[0].error_percent, 100.0 * (expected - exact) / exact, 1e-9);
}

TEST(LeaveOneOut, NeedsTwoScenes) {
  const std::vector<SceneMeasurement> one{model_scene("a", 1024, 1e-4, 0.1, 0.2, 0.0, 3.0, 1.0)};
  EXPECT_THROW(leave_one_out(one, RayKind::random), Error);
  EXPECT_THROW(leave_k_out(one, RayKind::random, 5, 1), Error);
}

TEST(LeaveKOut, ModelScenesHaveNoErrorForAnyK) {
  const auto scenes = model_scenes();
  const auto rows = leave_k_out(scenes, RayKind::random, 50, 7, 0.0);
  ASSERT_EQ(rows.size(), 3u);
  for (const LeaveKOutRow& row : rows) {
    EXPECT_EQ(row.splits, 50u);
    EXPECT_EQ(row.estimates + row.undefined, 50u * (4 - row.k));  // every (split, estimated scene) pair
    EXPECT_GT(row.undefined, 0u);                                  // scene c (exact R_C infinite) is drawn sometimes
    EXPECT_GT(row.estimates, 0u);
    EXPECT_NEAR(row.mean_error_percent, 0.0, 1e-9);
    EXPECT_NEAR(row.mean_abs_error_percent, 0.0, 1e-9);
  }
  EXPECT_EQ(rows[0].k, 1u);
  EXPECT_EQ(rows[2].k, 3u);
}

// Scenes whose grid is always slower per ray but whose costs do not follow one model: estimates err.
std::vector<SceneMeasurement> mixed_scenes() {
  return {model_scene("a", 1024, 1e-4, 0.1, 0.2, 0.3, 3.0, 4.0), model_scene("b", 4096, 2e-4, 0.15, 0.2, 0.7, 4.2, 5.4),
          model_scene("c", 65536, 0.7e-4, 0.1, 0.25, 5.0, 3.6, 13.2), model_scene("d", 256, 1.5e-4, 0.05, 0.1, 0.1, 10.8, 2.6),
          model_scene("e", 20000, 1.2e-4, 0.12, 0.18, 2.0, 6.0, 7.0)};
}

TEST(LeaveKOut, IsDeterministicInTheSeedAndAveragesOverSplits) {
  const auto scenes = mixed_scenes();
  const auto a = leave_k_out(scenes, RayKind::path, 30, 11);
  const auto b = leave_k_out(scenes, RayKind::path, 30, 11);
  const auto c = leave_k_out(scenes, RayKind::path, 30, 12);
  ASSERT_EQ(a.size(), 4u);
  bool any_difference = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].mean_error_percent, b[i].mean_error_percent);
    EXPECT_EQ(a[i].mean_abs_error_percent, b[i].mean_abs_error_percent);
    EXPECT_EQ(a[i].undefined, 0u);
    EXPECT_GE(a[i].mean_abs_error_percent, std::fabs(a[i].mean_error_percent));
    any_difference |= a[i].mean_error_percent != c[i].mean_error_percent;
  }
  EXPECT_TRUE(any_difference);  // another seed draws other splits
}

TEST(LeaveKOut, WithAllButOneCalibrationSceneItApproachesLeaveOneOut) {
  // k = n - 1: each split leaves out one uniformly drawn scene, so over many splits the mean error tends to
  // the mean of the leave-one-out errors.
  const auto scenes = mixed_scenes();
  const auto loo = leave_one_out(scenes, RayKind::random);
  double mean = 0.0, mean_abs = 0.0, spread = 0.0;
  for (const auto& row : loo) {
    mean += row.error_percent / 5.0;
    mean_abs += std::fabs(row.error_percent) / 5.0;
  }
  for (const auto& row : loo) spread = std::fmax(spread, std::fabs(row.error_percent - mean));
  ASSERT_GT(spread, 1.0);  // the test needs estimates that differ
  const auto rows = leave_k_out(scenes, RayKind::random, 4000, 3);
  const LeaveKOutRow& last = rows.back();
  EXPECT_EQ(last.k, 4u);
  EXPECT_EQ(last.estimates, 4000u);
  EXPECT_NEAR(last.mean_error_percent, mean, 0.1 * spread);
  EXPECT_NEAR(last.mean_abs_error_percent, mean_abs, 0.1 * spread);
}

TEST(DecisionAccuracy, CountsRightDecisionsAgainstMeasuredTotals) {
  auto scenes = model_scenes();
  const std::vector<double> rays{1.0, 1e3, 1e6};
  auto rows = decision_accuracy(scenes, RayKind::random, rays, 0.0);
  ASSERT_EQ(rows.size(), 3u);
  for (const DecisionRow& row : rows) {
    EXPECT_EQ(row.scenes, 4u);
    EXPECT_EQ(row.right, 4u);  // exact estimates, no ties
    EXPECT_NEAR(row.mean_time_ratio, 1.0, 1e-12);
  }
  // R = 1000: the kd-tree pays off on a (R_C 512) and d (20.48), not on b (4915) or c (never).
  EXPECT_EQ(rows[1].grid_right, 2u);
  EXPECT_EQ(rows[1].tree_right, 2u);
  EXPECT_EQ(rows[0].grid_right, 4u);  // one ray never pays for a build
  EXPECT_EQ(rows[2].tree_right, 3u);

  // A misleading sample on d (grid looks fast): the decision keeps the grid where the kd-tree wins.
  scenes[3].rays[calibrated_kind_index(RayKind::random)].grid_sample_us = 0.5;
  rows = decision_accuracy(scenes, RayKind::random, rays, 0.0);
  EXPECT_EQ(rows[0].right, 4u);
  EXPECT_EQ(rows[1].right, 3u);
  EXPECT_EQ(rows[2].right, 3u);
  const double grid_d = 1e3 * 10.8e-3, tree_d = 0.2048 + 1e3 * 0.8e-3;
  EXPECT_NEAR(rows[1].mean_time_ratio, (3.0 + grid_d / tree_d) / 4.0, 1e-9);
}

TEST(DecisionAccuracy, AKdTreePickPaysForTheDiscardedGrid) {
  std::vector<SceneMeasurement> scenes{model_scene("a", 1024, 1e-4, 0.1, 0.2, 0.5, 3.0, 1.0),
                                       model_scene("b", 4096, 1e-4, 0.1, 0.2, 0.5, 2.2, 4.4)};
  const std::vector<double> rays{1e7};
  const auto rows = decision_accuracy(scenes, RayKind::random, rays, 0.0);
  ASSERT_EQ(rows[0].right, 2u);
  const double a_tree = tree_total_ms(scenes[0], RayKind::random, 1e7), b_tree = tree_total_ms(scenes[1], RayKind::random, 1e7);
  EXPECT_NEAR(rows[0].mean_time_ratio, 0.5 * ((0.5 + a_tree) / a_tree + (0.5 + b_tree) / b_tree), 1e-12);
  EXPECT_DOUBLE_EQ(grid_total_ms(scenes[0], RayKind::random, 1e7), 0.5 + 1e7 * 3e-3);
}

}  // namespace
}  // namespace vf
