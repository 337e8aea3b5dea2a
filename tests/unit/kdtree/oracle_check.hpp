#pragma once
/// \file Ray-by-ray comparison of a kd structure with the BruteForce oracle.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/same_hit.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

/// Rays with the oracle's closest hits, computed once for several structures.
struct OracleRays {
  std::vector<Ray> rays;
  std::vector<Hit> expected;

  OracleRays(const TriangleSet& set, std::vector<Ray> rays_) : rays(std::move(rays_)) {
    const BruteForce oracle = BruteForce::build(set);
    expected.reserve(rays.size());
    for (const Ray& r : rays) expected.push_back(oracle.intersect(r));
  }
};

inline std::string describe_hit(const Hit& h) {
  return h ? "t " + std::to_string(h.t) + " prim " + std::to_string(h.prim) : std::string("miss");
}

/// Expects closest hits bit-identical to the oracle's (ties: lowest index) and occluded() equal to
/// "a hit exists" for every ray; stops at the first mismatch. Returns how many rays hit.
template <Accelerator A>
std::size_t expect_matches_oracle(const A& accel, const OracleRays& oracle, const std::string& label) {
  std::size_t hits = 0;
  for (std::size_t i = 0; i < oracle.rays.size(); ++i) {
    const Hit& expected = oracle.expected[i];
    const Hit got = accel.intersect(oracle.rays[i]);
    const bool occluded = accel.occluded(oracle.rays[i]);
    EXPECT_TRUE(same_bits(got, expected))
        << label << ": ray " << i << " expected " << describe_hit(expected) << ", got " << describe_hit(got);
    EXPECT_EQ(occluded, expected.found) << label << ": occluded() of ray " << i;
    if (!same_bits(got, expected) || occluded != expected.found) return hits;
    hits += expected ? 1 : 0;
  }
  return hits;
}

}  // namespace vf::test
