// The paper's grid statistics (sparseness, maxRefs, mean, variance, skewness, kurtosis) on grids
// whose per-cell counts are known by construction, checked against values worked out by hand.

#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "unit/grid/grid_test_support.hpp"
#include "visfield/accel/grid_stats.hpp"

namespace vf {
namespace {

using test::set_from_triangles;
using test::small_triangle;
using test::Triangle;

// Expects `s` to equal `expected`: counts exactly, moments to the last few bits.
void expect_statistics(const GridStatistics& s, const GridStatistics& expected) {
  EXPECT_EQ(s.cell_count, expected.cell_count);
  EXPECT_EQ(s.empty_cells, expected.empty_cells);
  EXPECT_EQ(s.max_refs, expected.max_refs);
  EXPECT_DOUBLE_EQ(s.sparseness, expected.sparseness);
  EXPECT_DOUBLE_EQ(s.mean, expected.mean);
  EXPECT_DOUBLE_EQ(s.variance, expected.variance);
  EXPECT_DOUBLE_EQ(s.std_dev, expected.std_dev);
  EXPECT_DOUBLE_EQ(s.skewness, expected.skewness);
  EXPECT_DOUBLE_EQ(s.kurtosis, expected.kurtosis);
}

TEST(GridStats, HandBuiltSceneWithKnownCellCounts) {
  // 4 x 4 x 4 unit cells on [0, 4]^3, so t = 64. By construction:
  //   cell (0, 0, 0): 3 triangles; cell (1, 2, 3): 2; cell (3, 3, 3): 1;
  //   one triangle crossing the plane x = 2, inside cells (1, 1, 1) and (2, 1, 1): 1 each.
  const std::vector<Triangle> triangles{
      small_triangle({0.5f, 0.5f, 0.3f}), small_triangle({0.5f, 0.5f, 0.5f}), small_triangle({0.4f, 0.6f, 0.7f}),
      small_triangle({1.5f, 2.5f, 3.4f}), small_triangle({1.5f, 2.5f, 3.6f}), small_triangle({3.5f, 3.5f, 3.5f}),
      {Vec3f{1.6f, 1.4f, 1.5f}, Vec3f{2.4f, 1.4f, 1.5f}, Vec3f{2.0f, 1.6f, 1.5f}},
  };
  const UniformGrid grid = UniformGrid::build(set_from_triangles(triangles), test::unit_cells(4));
  const GridGeometry& L = grid.geometry();
  ASSERT_EQ(grid.cell_references(L.cell_index(0, 0, 0)).size(), 3u);
  ASSERT_EQ(grid.cell_references(L.cell_index(1, 2, 3)).size(), 2u);
  ASSERT_EQ(grid.cell_references(L.cell_index(3, 3, 3)).size(), 1u);
  ASSERT_EQ(grid.cell_references(L.cell_index(1, 1, 1)).size(), 1u);
  ASSERT_EQ(grid.cell_references(L.cell_index(2, 1, 1)).size(), 1u);
  ASSERT_EQ(grid.stats().reference_count, 8u);

  // N_i = {3, 2, 1, 1, 1} and 59 zeros; mean = 8 / 64 = 0.125. Deviations N_i - mean:
  // 2.875, 1.875, 0.875 (x3), -0.125 (x59). Their sums of powers:
  //   squares: 8.265625 + 3.515625 + 3 * 0.765625 + 59 * 0.015625 = 15
  //   cubes:   23.763671875 + 6.591796875 + 3 * 0.669921875 - 59 * 0.001953125 = 32.25
  //   fourths: 68.320556640625 + 12.359619140625 + 3 * 0.586181640625 + 59 * 0.000244140625 = 82.453125
  const double variance = 15.0 / 63.0;  // the paper divides by t - 1
  const double sigma = std::sqrt(variance);
  const GridStatistics s = compute_grid_statistics(grid);
  expect_statistics(s, {.cell_count = 64,
                        .empty_cells = 59,
                        .sparseness = 59.0 / 64.0,
                        .max_refs = 3,
                        .mean = 0.125,
                        .variance = variance,
                        .std_dev = sigma,
                        .skewness = 32.25 / 64.0 / (sigma * sigma * sigma),
                        .kurtosis = 82.453125 / 64.0 / (variance * variance) - 3.0});
  EXPECT_NEAR(s.skewness, 4.3373421289, 1e-9);
  EXPECT_NEAR(s.kurtosis, 19.7261425781, 1e-9);
}

TEST(GridStats, EqualCountsHaveNoSpread) {
  // Two cells of [0, 2] x [0, 1] x [0, 1], one triangle in each: N_i = {1, 1}.
  UniformGridConfig config;
  config.resolution = {2, 1, 1};
  config.box = Bounds3f{Vec3f{0, 0, 0}, Vec3f{2, 1, 1}};
  const UniformGrid grid =
      UniformGrid::build(set_from_triangles({small_triangle({0.5f, 0.5f, 0.5f}), small_triangle({1.5f, 0.5f, 0.5f})}), config);
  // Skewness and kurtosis are undefined for sigma = 0; reported as 0.
  EXPECT_EQ(compute_grid_statistics(grid), (GridStatistics{.cell_count = 2, .max_refs = 1, .mean = 1.0}));
}

TEST(GridStats, CountsGivenAsOffsets) {
  // N_i = {4, 0, 1, 0, 0, 2, 0, 0, 2}: t = 9, sum 9, mean 1, empty 5.
  // Deviations 3, -1, 0, -1, -1, 1, -1, -1, 1: squares sum 16, cubes 27 - 5 + 2 = 24, fourths 81 + 5 + 2 = 88.
  const std::vector<std::uint32_t> starts{0, 4, 4, 5, 5, 5, 7, 7, 7, 9};
  const GridStatistics s = compute_grid_statistics(starts);
  const double sigma = std::sqrt(2.0);
  expect_statistics(s, {.cell_count = 9,
                        .empty_cells = 5,
                        .sparseness = 5.0 / 9.0,
                        .max_refs = 4,
                        .mean = 1.0,
                        .variance = 16.0 / 8.0,
                        .std_dev = sigma,
                        .skewness = 24.0 / 9.0 / (2.0 * sigma),
                        .kurtosis = 88.0 / 9.0 / 4.0 - 3.0});
}

TEST(GridStats, SingleCellAndEmptyGrids) {
  const std::vector<std::uint32_t> one_cell{0, 5};
  const GridStatistics one = compute_grid_statistics(one_cell);
  EXPECT_EQ(one.cell_count, 1u);
  EXPECT_EQ(one.max_refs, 5u);
  EXPECT_EQ(one.mean, 5.0);
  EXPECT_EQ(one.variance, 0.0);  // 1 / (t - 1) is undefined for t = 1; reported as 0
  const GridStatistics none = compute_grid_statistics(UniformGrid::build(TriangleSet{}));
  EXPECT_EQ(none.cell_count, 0u);
  EXPECT_EQ(none.sparseness, 0.0);
  EXPECT_EQ(none.mean, 0.0);
}

}  // namespace
}  // namespace vf
