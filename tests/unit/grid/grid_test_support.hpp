#pragma once
/// \file Shared by the grid tests: comparison of a grid's answers with the BruteForce oracle, and
/// small scenes with a known cell geometry.

#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "differential/test_scenes.hpp"
#include "support/same_hit.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/uniform_grid.hpp"

namespace vf::test {

/// Human-readable ray for failure messages (hexadecimal floats, exact).
inline std::string ray_text(const Ray& r) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "org=(%a, %a, %a) dir=(%a, %a, %a) tmin=%a tmax=%a", r.org.x, r.org.y, r.org.z,
                r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
  return buf;
}

/// Asserts that `grid` answers every ray exactly as BruteForce over `set` does: closest hits
/// bit-identical (t, u, v, triangle; ties go to the lowest index in both) and the same occlusion.
/// Returns the number of rays the oracle hits.
inline std::size_t expect_same_as_oracle(const UniformGrid& grid, const TriangleSet& set, std::span<const Ray> rays,
                                         const std::string& label) {
  const BruteForce oracle = BruteForce::build(set);
  std::size_t hits = 0, failures = 0;
  for (std::size_t i = 0; i < rays.size() && failures < 5; ++i) {
    const Hit expected = oracle.intersect(rays[i]);
    const Hit got = grid.intersect(rays[i]);
    hits += expected.found ? 1 : 0;
    if (!same_bits(got, expected)) {
      ++failures;
      ADD_FAILURE() << label << ": closest hit differs on ray " << i << " " << ray_text(rays[i]) << "\n  oracle "
                    << (expected ? std::to_string(expected.t) + " prim " + std::to_string(expected.prim) : "miss")
                    << "\n  grid   " << (got ? std::to_string(got.t) + " prim " + std::to_string(got.prim) : "miss");
    }
    if (grid.occluded(rays[i]) != oracle.occluded(rays[i])) {
      ++failures;
      ADD_FAILURE() << label << ": occluded differs on ray " << i << " " << ray_text(rays[i]);
    }
  }
  return hits;
}

/// A small axis-aligned triangle of half-size `s` in the plane z = c.z, centred at c.
inline Triangle small_triangle(Vec3f c, float s = 0.1f) {
  return {Vec3f{c.x - s, c.y - s, c.z}, Vec3f{c.x + s, c.y - s, c.z}, Vec3f{c.x, c.y + s, c.z}};
}

/// Config forcing an n x n x n grid on the box [0, n]^3, so cell (x, y, z) is [x, x+1] x [y, y+1] x [z, z+1].
inline UniformGridConfig unit_cells(int n) {
  UniformGridConfig config;
  config.resolution = {n, n, n};
  config.box = Bounds3f{Vec3f{0.0f}, Vec3f{static_cast<float>(n)}};
  return config;
}

}  // namespace vf::test
