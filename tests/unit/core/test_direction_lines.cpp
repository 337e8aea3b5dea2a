// The octahedral line set of BeamField: counts, exact nearest-line lookup against brute force,
// the covering angle, and the PSF frames.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "visfield/core/direction_lines.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"

namespace vf {
namespace {

double dot_precise(const Vec3f& d, const std::array<double, 3>& w) {
  return static_cast<double>(d.x) * w[0] + static_cast<double>(d.y) * w[1] + static_cast<double>(d.z) * w[2];
}

// argmax_k |d·ω_k| over every line, with the orientation sgn(d·ω_k).
NearestLine brute_force_nearest(const DirectionLines& lines, const Vec3f& d, double& best_cos) {
  NearestLine best;
  best_cos = -1.0;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const double c = dot_precise(d, lines.direction_precise(k));
    if (std::fabs(c) > best_cos) {
      best_cos = std::fabs(c);
      best = {static_cast<std::uint32_t>(k), c >= 0.0 ? 1 : -1};
    }
  }
  return best;
}

TEST(DirectionLines, CountsAreTwoNSquaredPlusOne) {
  const std::size_t expected[] = {33, 129, 513, 2049, 8193};
  for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level) {
    const DirectionLines lines(level);
    EXPECT_EQ(lines.size(), expected[level - 2]);
    EXPECT_EQ(DirectionLines::count(level), expected[level - 2]);
    EXPECT_EQ(lines.lattice_size(), 1 << level);
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const auto& w = lines.direction_precise(k);
      EXPECT_NEAR(w[0] * w[0] + w[1] * w[1] + w[2] * w[2], 1.0, 1e-14);
      EXPECT_GE(w[2], 0.0);
    }
  }
  EXPECT_THROW(DirectionLines(1), Error);
  EXPECT_THROW(DirectionLines(7), Error);
}

TEST(DirectionLines, LinesAreDistinctAndNoTwoAreAntipodal) {
  const DirectionLines lines(4);
  for (std::size_t a = 0; a < lines.size(); ++a)
    for (std::size_t b = a + 1; b < lines.size(); ++b) {
      const auto& p = lines.direction_precise(a);
      const auto& q = lines.direction_precise(b);
      EXPECT_LT(std::fabs(p[0] * q[0] + p[1] * q[1] + p[2] * q[2]), 1.0 - 1e-6) << a << " " << b;
    }
}

TEST(DirectionLines, EveryLineFindsItselfInBothOrientations) {
  for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level) {
    const DirectionLines lines(level);
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const NearestLine forward = lines.nearest(lines.direction(k));
      EXPECT_EQ(forward.line, k) << "level " << level;
      EXPECT_EQ(forward.sign, 1);
      const NearestLine backward = lines.nearest(-lines.direction(k));
      EXPECT_EQ(backward.line, k) << "level " << level;
      EXPECT_EQ(backward.sign, -1);
    }
  }
}

// Random directions, directions on and near the equator, on the coordinate planes, and on lattice
// cell edges (between two neighbouring lines), any length: the lookup is brute force's argmax.
TEST(DirectionLines, LookupIsTheNearestLineOfBruteForce) {
  Rng rng(7, 1);
  for (int level = DirectionLines::kMinLevel; level <= 5; ++level) {
    const DirectionLines lines(level);
    std::vector<Vec3f> queries;
    for (int q = 0; q < 20000; ++q) queries.push_back(uniform_sphere(rng.uniform(), rng.uniform()) * (0.5f + rng.uniform()));
    for (int q = 0; q < 5000; ++q) {
      const float phi = 2.0f * std::numbers::pi_v<float> * rng.uniform();
      const float z = (rng.uniform() - 0.5f) * 1e-3f * static_cast<float>(q % 3);  // exactly 0 for a third
      queries.push_back({std::cos(phi), std::sin(phi), z});
    }
    for (int q = 0; q < 2000; ++q) {
      const float t = 2.0f * rng.uniform() - 1.0f, s = 2.0f * rng.uniform() - 1.0f;
      queries.push_back({t, 0.0f, s});
      queries.push_back({0.0f, t, s});
      queries.push_back({t, s, 0.0f});
    }
    for (int q = 0; q < 5000; ++q) {  // half-way between a line and a neighbour: on a cell edge
      const Vec3f a = lines.direction(rng.next_u32() % lines.size());
      const Vec3f p = a + uniform_sphere(rng.uniform(), rng.uniform()) * (2.0f / static_cast<float>(lines.lattice_size()));
      const NearestLine near = lines.nearest(p);
      queries.push_back(a + lines.direction(near.line) * static_cast<float>(near.sign));
    }
    queries.push_back({1, 0, 0});
    queries.push_back({-1, 0, 0});
    queries.push_back({0, 1, 0});
    queries.push_back({0, -1, 0});
    queries.push_back({0, 0, 1});
    queries.push_back({0, 0, -1});
    std::size_t wrong = 0;
    for (const Vec3f& d : queries) {
      if (!(length(d) > 0.0f)) continue;
      double best_cos = 0.0;
      const NearestLine expected = brute_force_nearest(lines, d, best_cos);
      const NearestLine got = lines.nearest(d);
      const double got_cos = dot_precise(d, lines.direction_precise(got.line));
      // Ties (equal |cos| up to rounding) may go either way; the orientation must match the line found.
      const bool same = got.line == expected.line && got.sign == expected.sign;
      const bool tie = std::fabs(std::fabs(got_cos) - best_cos) <= 1e-12 * length(d) && (got_cos >= 0.0) == (got.sign > 0);
      wrong += !(same || tie);
      if (!(same || tie) && wrong < 5)
        ADD_FAILURE() << "level " << level << " d (" << d.x << ", " << d.y << ", " << d.z << "): got line " << got.line
                      << " sign " << got.sign << " |cos| " << std::fabs(got_cos) << ", brute force line " << expected.line
                      << " sign " << expected.sign << " |cos| " << best_cos;
    }
    EXPECT_EQ(wrong, 0u) << "level " << level << " over " << queries.size() << " queries";
  }
}

// The worst angle between a direction and its line (the covering radius): at most the stated bound,
// and random queries come within 5% of it.
TEST(DirectionLines, CoveringAngleMatchesTheDesign) {
  const double bound_deg[] = {8.82, 4.47, 2.26, 1.15};  // levels 3..6
  Rng rng(11, 2);
  for (int level = 3; level <= 6; ++level) {
    const DirectionLines lines(level);
    double worst = 0.0;
    for (int q = 0; q < 1000000; ++q) {
      const Vec3f d = uniform_sphere(rng.uniform(), rng.uniform());
      const NearestLine near = lines.nearest(d);
      const double c = std::fabs(dot_precise(d, lines.direction_precise(near.line))) / length(d);
      worst = std::max(worst, std::acos(std::min(1.0, c)) * 180.0 / std::numbers::pi);
    }
    const double bound = bound_deg[level - 3];
    std::printf("  level %d: %zu lines, worst angle to the nearest line over 1M directions %.3f deg (design %.2f)\n", level,
                lines.size(), worst, bound);
    EXPECT_LE(worst, bound * 1.005) << "level " << level;
    EXPECT_GE(worst, 0.95 * bound) << "level " << level;
  }
}

TEST(DirectionLines, FramesAreOrthonormalRightHandedAndIdentityAtTheZenith) {
  const DirectionLines lines(4);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const PsfFrame& f = lines.frame(k);
    EXPECT_EQ(f.w, lines.direction(k));
    EXPECT_NEAR(dot(f.u, f.u), 1.0f, 1e-6f);
    EXPECT_NEAR(dot(f.v, f.v), 1.0f, 1e-6f);
    EXPECT_NEAR(dot(f.u, f.v), 0.0f, 1e-6f);
    EXPECT_NEAR(dot(f.u, f.w), 0.0f, 1e-6f);
    EXPECT_NEAR(dot(f.v, f.w), 0.0f, 1e-6f);
    const Vec3f c = cross(f.u, f.v);
    EXPECT_NEAR(c.x, f.w.x, 1e-6f);
    EXPECT_NEAR(c.y, f.w.y, 1e-6f);
    EXPECT_NEAR(c.z, f.w.z, 1e-6f);
  }
  const PsfFrame& zenith = lines.frame(lines.nearest({0, 0, 1}).line);
  EXPECT_EQ(zenith.u, (Vec3f{1, 0, 0}));
  EXPECT_EQ(zenith.v, (Vec3f{0, 1, 0}));
  EXPECT_EQ(zenith.w, (Vec3f{0, 0, 1}));
}

// A beam is a line: a ray and its reverse fall in the same beam, at opposite orientations.
TEST(DirectionLines, BeamCoordinatesDoNotDependOnTheRaysOrientation) {
  const DirectionLines lines(4);
  Rng rng(3, 3);
  for (int q = 0; q < 1000; ++q) {
    const Vec3f d = uniform_sphere(rng.uniform(), rng.uniform());
    const Vec3f p{rng.uniform(), rng.uniform(), rng.uniform()};
    const NearestLine a = lines.nearest(d), b = lines.nearest(-d);
    ASSERT_EQ(a.line, b.line);
    ASSERT_EQ(a.sign, -b.sign);
    const PsfFrame& f = lines.frame(a.line);
    EXPECT_EQ(dot(f.u, p), dot(lines.frame(b.line).u, p));
    EXPECT_EQ(dot(f.v, p), dot(lines.frame(b.line).v, p));
  }
}

}  // namespace
}  // namespace vf
