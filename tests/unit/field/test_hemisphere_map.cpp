// The square <-> hemisphere maps of ObjectField direction tables: round trips, every cell's
// direction falls back in its cell, and the cells' measures (projected solid angle for the
// Malley lifts, solid angle for the equal-area one) counted from independently drawn directions.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "visfield/core/rng.hpp"
#include "visfield/field/hemisphere_map.hpp"

namespace vf::field {
namespace {

using V = hd::Vec3<double>;
constexpr double kPi = 3.14159265358979323846;
const HemisphereMapping kAll[] = {HemisphereMapping::polar, HemisphereMapping::rejection_malley,
                                  HemisphereMapping::concentric_malley, HemisphereMapping::concentric_equal_area};

TEST(HemisphereMap, DirectionsAreUnitAndRoundTripToTheirSquarePoint) {
  Rng rng(7);
  for (const HemisphereMapping m : kAll) {
    for (int q = 0; q < 100000; ++q) {
      const double s = 0.001 + 0.998 * rng.uniform(), t = 0.001 + 0.998 * rng.uniform();
      if (m == HemisphereMapping::rejection_malley && (2 * s - 1) * (2 * s - 1) + (2 * t - 1) * (2 * t - 1) > 1.0) continue;
      const V w = square_to_direction(m, s, t);
      EXPECT_NEAR(hd::dot(w, w), 1.0, 1e-12);
      EXPECT_GE(w.z, 0.0);
      double s2, t2;
      direction_to_square(m, w, s2, t2);
      ASSERT_NEAR(s2, s, 1e-9) << static_cast<int>(m) << " " << s << " " << t;
      ASSERT_NEAR(t2, t, 1e-9) << static_cast<int>(m) << " " << s << " " << t;
    }
  }
}

TEST(HemisphereMap, EveryUsedCellsDirectionLooksUpItsOwnCell) {
  for (const HemisphereMapping m : kAll) {
    for (const int n : {8, 32, 64, 256}) {
      int used = 0;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          if (!cell_used<double>(m, i, j, n)) continue;
          ++used;
          const V w = cell_direction<double>(m, i, j, n);
          double s, t;
          direction_to_square(m, w, s, t);
          ASSERT_EQ(cell_of(s, n), i) << static_cast<int>(m) << " n=" << n << " cell " << i << "," << j;
          ASSERT_EQ(cell_of(t, n), j) << static_cast<int>(m) << " n=" << n << " cell " << i << "," << j;
        }
      if (m == HemisphereMapping::rejection_malley)
        EXPECT_NEAR(1.0 - static_cast<double>(used) / (n * n), 1.0 - kPi / 4.0, 4.0 / n);  // about 21.5% unused
      else
        EXPECT_EQ(used, n * n);
    }
  }
}

// Counts of 4M directions drawn without the maps (polar coordinates) per cell of a 16×16 table:
// cosine-weighted directions fill the Malley cells evenly, uniform ones the equal-area cells.
TEST(HemisphereMap, ConcentricCellsHaveEqualMeasure) {
  constexpr int n = 16;
  constexpr int draws = 4000000;
  const double expected = static_cast<double>(draws) / (n * n);  // 15625; sd 125
  for (const HemisphereMapping m : {HemisphereMapping::concentric_malley, HemisphereMapping::concentric_equal_area}) {
    std::vector<int> count(n * n, 0);
    Rng rng(99);
    for (int q = 0; q < draws; ++q) {
      const double u1 = rng.uniform(), phi = 2.0 * kPi * rng.uniform();
      const double cos_theta = m == HemisphereMapping::concentric_malley ? std::sqrt(1.0 - u1) : 1.0 - u1;
      const double sin_theta = std::sqrt(std::fmax(0.0, 1.0 - cos_theta * cos_theta));
      double s, t;
      direction_to_square(m, V{sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta}, s, t);
      ++count[cell_of(s, n) * n + cell_of(t, n)];
    }
    for (int c = 0; c < n * n; ++c) EXPECT_NEAR(count[c], expected, 6.0 * std::sqrt(expected)) << static_cast<int>(m) << " cell " << c;
  }
}

TEST(HemisphereMap, PolarCellsCrowdAtThePole) {
  // Equal angles: a cell in the first row (θ < 90°/N) covers far less solid angle than one at the
  // horizon, the non-uniformity the paper's Figure 5 shows.
  constexpr int n = 32;
  const auto solid_angle_of_row = [&](int j) {
    const double t0 = static_cast<double>(j) / n, t1 = static_cast<double>(j + 1) / n;
    return 2.0 * kPi * (std::cos(kPi / 2 * t0) - std::cos(kPi / 2 * t1)) / n;
  };
  EXPECT_GT(solid_angle_of_row(n - 1) / solid_angle_of_row(0), 30.0);
  double s, t;
  direction_to_square(HemisphereMapping::polar, V{0.0, 0.0, 1.0}, s, t);
  EXPECT_EQ(cell_of(t, n), 0);
  direction_to_square(HemisphereMapping::polar, V{1.0, 0.0, 0.0}, s, t);
  EXPECT_EQ(cell_of(t, n), n - 1);
  EXPECT_EQ(cell_of(s, n), 0);
}

TEST(HemisphereMap, FloatLookupAgreesWithDoubleAwayFromCellBorders) {
  Rng rng(3);
  for (const HemisphereMapping m : kAll) {
    int disagreements = 0;
    for (int q = 0; q < 100000; ++q) {
      const int n = 64;
      const int i = static_cast<int>(rng.uniform() * n), j = static_cast<int>(rng.uniform() * n);
      if (!cell_used<double>(m, i, j, n)) continue;
      const V w = cell_direction<double>(m, i, j, n);
      float s, t;
      direction_to_square(m, hd::Vec3<float>{static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z)}, s, t);
      disagreements += cell_of(s, n) != i || cell_of(t, n) != j;
    }
    EXPECT_EQ(disagreements, 0) << static_cast<int>(m);
  }
}

}  // namespace
}  // namespace vf::field
