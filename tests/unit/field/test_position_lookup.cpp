// The ObjectField's positional samples: counts, the O(1) nearest sample against brute force on
// random and adversarial directions (equator, poles, the samples themselves, lattice edges), in
// double and in float, the lookups' heaviest corner against the nearest, and the three-sample blend.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "support/test_scale.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/field/sphere_positions.hpp"

namespace vf::field {
namespace {

using V = hd::Vec3<double>;

V normalized(double x, double y, double z) {
  const double l = std::sqrt(x * x + y * y + z * z);
  return {x / l, y / l, z / l};
}

// argmax over every sample of cos(d, sample).
double brute_force_best_cos(const SpherePositions& set, const V& d) {
  double best = -2.0;
  for (std::size_t k = 0; k < set.size(); ++k) best = std::fmax(best, hd::dot(d, set.direction(k)));
  return best;
}

// Random directions, 10% of them within 1e-3 of the equator, plus the adversarial ones.
std::vector<V> query_directions(const SpherePositions& set, std::size_t random_count) {
  std::vector<V> out;
  Rng rng(2024);
  for (std::size_t q = 0; q < random_count; ++q) {
    const Vec3f d = uniform_sphere(rng.uniform(), rng.uniform());
    if (q % 10 == 0)
      out.push_back(normalized(d.x, d.y, (rng.uniform() - 0.5) * 2e-3));
    else
      out.push_back(normalized(d.x, d.y, d.z));
  }
  for (std::size_t k = 0; k < set.size(); ++k) out.push_back(set.direction(k));
  for (const V& axis : {V{1, 0, 0}, V{-1, 0, 0}, V{0, 1, 0}, V{0, -1, 0}, V{0, 0, 1}, V{0, 0, -1}, V{1, 0, 0.0}}) out.push_back(axis);
  for (int k = 0; k < 1000; ++k) {  // on the equator exactly, and on lattice diagonals
    const double phi = 2.0 * 3.141592653589793 * k / 1000.0;
    out.push_back(normalized(std::cos(phi), std::sin(phi), 0.0));
    out.push_back(normalized(std::cos(phi), std::cos(phi), std::sin(phi)));
  }
  return out;
}

TEST(SpherePositions, CountsAreThePapersFour) {
  const std::size_t expected[] = {290, 1090, 4226, 16642};
  for (int level = SpherePositions::kMinLevel; level <= SpherePositions::kMaxLevel; ++level) {
    EXPECT_EQ(SpherePositions::count(level), expected[level - SpherePositions::kMinLevel]);
    EXPECT_EQ(SpherePositions(level).size(), expected[level - SpherePositions::kMinLevel]);
  }
  EXPECT_THROW(SpherePositions(2), Error);
  EXPECT_THROW(SpherePositions(7), Error);
}

TEST(SpherePositions, SamplesAreUnitAndTheLowerHalfMirrorsTheUpper) {
  const SpherePositions set(4);
  const std::size_t half = set.size() / 2;
  for (std::size_t k = 0; k < half; ++k) {
    const V u = set.direction(k), l = set.direction(k + half);
    EXPECT_NEAR(hd::dot(u, u), 1.0, 1e-15);
    EXPECT_GE(u.z, 0.0);
    EXPECT_EQ(l.x, u.x);
    EXPECT_EQ(l.y, u.y);
    EXPECT_EQ(l.z, -u.z);
    // The float table is computed in float (polynomial sine and cosine), within float rounding of the double one.
    const hd::Vec3<float> f = set.upper_table()[k];
    EXPECT_NEAR(f.x, u.x, 3e-7);
    EXPECT_NEAR(f.y, u.y, 3e-7);
    EXPECT_NEAR(f.z, u.z, 3e-7);
  }
}

TEST(SpherePositions, NearestEqualsBruteForceInDoubleAndNearlyInFloat) {
  for (int level = 3; level <= 5; ++level) {
    const SpherePositions set(level);
    std::size_t mismatches = 0, float_worse = 0;
    for (const V& d : query_directions(set, test::scaled_count(30000))) {
      const double best = brute_force_best_cos(set, d);
      const std::size_t k = set.nearest(d);
      ASSERT_LT(k, set.size());
      // Ties (the equator ring, stored twice; points equidistant from two samples) may pick either.
      if (hd::dot(d, set.direction(k)) < best - 1e-14) ++mismatches;
      const hd::Vec3<float> f{static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)};
      const int kf = nearest_position(f, set.lattice_size(), set.upper_table());
      if (hd::dot(d, set.direction(static_cast<std::size_t>(kf))) < best - 1e-6) ++float_worse;
    }
    EXPECT_EQ(mismatches, 0u) << "level " << level;
    EXPECT_EQ(float_worse, 0u) << "level " << level;
  }
}

TEST(SpherePositions, EverySampleIsItsOwnNearest) {
  const SpherePositions set(5);
  const std::size_t half = set.size() / 2;
  for (std::size_t k = 0; k < set.size(); ++k) {
    const V d = set.direction(k);
    const std::size_t found = set.nearest(d);
    if (d.z == 0.0) {  // the equator ring: either copy
      EXPECT_TRUE(found == k || found + half == k || found == k + half) << k;
    } else {
      EXPECT_EQ(found, k);
    }
  }
}

// The lookups' sample: the heaviest corner of the direction's lattice triangle. It is one of the
// corners nearest_position() compares, it is the nearest sample for most directions, and where it is
// not it lies at most a little farther than the farthest any direction lies from its nearest sample.
TEST(SpherePositions, HeaviestCornerIsNearlyAlwaysTheNearestAndNeverFar) {
  for (int level = 3; level <= 6; ++level) {
    const SpherePositions set(level);
    std::size_t other = 0, count = 0;
    double worst_nearest = 0.0, worst_heaviest = 0.0;
    for (const V& d : query_directions(set, test::scaled_count(30000))) {
      const hd::Vec3<float> f{static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)};
      const int heaviest = heaviest_corner_position(f, set.lattice_size());
      ASSERT_GE(heaviest, 0);
      ASSERT_LT(static_cast<std::size_t>(heaviest), set.size());
      const std::size_t nearest = set.nearest(d);
      const double cos_heaviest = hd::dot(d, set.direction(static_cast<std::size_t>(heaviest)));
      const double cos_nearest = hd::dot(d, set.direction(nearest));
      if (cos_heaviest < cos_nearest - 1e-12) ++other;
      ++count;
      worst_nearest = std::fmax(worst_nearest, std::acos(std::fmin(1.0, cos_nearest)));
      worst_heaviest = std::fmax(worst_heaviest, std::acos(std::fmin(1.0, cos_heaviest)));
    }
    // Measured: 7.5% of uniform directions at every level, the farthest 1.18x the nearest's farthest.
    EXPECT_LT(static_cast<double>(other), 0.10 * static_cast<double>(count)) << "level " << level;
    EXPECT_GT(other, 0u) << "level " << level << ": the pick is not nearest_position under another name";
    EXPECT_LT(worst_heaviest, 1.25 * worst_nearest) << "level " << level;
  }
}

TEST(SpherePositions, EverySampleIsItsOwnHeaviestCorner) {
  const SpherePositions set(5);
  const std::size_t half = set.size() / 2;
  for (std::size_t k = 0; k < set.size(); ++k) {
    const V d = set.direction(k);
    const hd::Vec3<float> f{static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)};
    const auto found = static_cast<std::size_t>(heaviest_corner_position(f, set.lattice_size()));
    if (d.z == 0.0) {  // the equator ring: either copy
      EXPECT_TRUE(found == k || found + half == k || found == k + half) << k;
    } else {
      // A sample's direction in float lies within rounding of its lattice point: weight ~1 there.
      EXPECT_EQ(found, k);
    }
  }
}

TEST(SpherePositions, BlendWeightsArePositiveSumToOneAndPickASampleAtItsDirection) {
  const SpherePositions set(4);
  for (const V& d : query_directions(set, 20000)) {
    const PositionBlend<double> b = set.blend(d);
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(b.index[k], 0);
      ASSERT_LT(static_cast<std::size_t>(b.index[k]), set.size());
      EXPECT_GE(b.weight[k], 0.0);
      sum += b.weight[k];
      // A sample with weight is a corner of d's triangle: within one lattice cell of d.
      if (b.weight[k] > 0.0) {
        EXPECT_GT(hd::dot(d, set.direction(static_cast<std::size_t>(b.index[k]))), std::cos(0.3));
      }
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
  for (std::size_t k = 0; k < set.size(); ++k) {
    const V d = set.direction(k);
    const PositionBlend<double> b = set.blend(d);
    double on_sample = 0.0;
    for (int c = 0; c < 3; ++c)
      if (hd::dot(set.direction(static_cast<std::size_t>(b.index[c])), d) > 1.0 - 1e-12) on_sample += b.weight[c];
    EXPECT_NEAR(on_sample, 1.0, 1e-9) << k;
  }
}

}  // namespace
}  // namespace vf::field
