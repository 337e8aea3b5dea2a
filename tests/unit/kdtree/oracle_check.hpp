#pragma once
/// \file Ray-by-ray comparison of a kd structure with the scalar brute-force definition.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "unit/accel/scalar_reference.hpp"
#include "visfield/accel/accelerator.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

/// Rays with their expected closest hits (scalar_closest), computed once for several structures.
struct OracleRays {
  std::vector<Ray> rays;
  std::vector<std::optional<Hit>> expected;

  OracleRays(const TriangleSet& set, std::vector<Ray> rays_) : rays(std::move(rays_)) {
    expected.reserve(rays.size());
    for (const Ray& r : rays) expected.push_back(scalar_closest(set, r));
  }
};

inline std::string describe_hit(const std::optional<Hit>& h) {
  return h ? "t " + std::to_string(h->t) + " prim " + std::to_string(h->prim) : std::string("miss");
}

/// Expects closest hits bit-identical to scalar_closest (ties: lowest index) and occluded() equal to
/// "a hit exists" for every ray; stops at the first mismatch. Returns how many rays hit.
template <Accelerator A>
std::size_t expect_matches_oracle(const A& accel, const OracleRays& oracle, const std::string& label) {
  std::size_t hits = 0;
  for (std::size_t i = 0; i < oracle.rays.size(); ++i) {
    const std::optional<Hit>& expected = oracle.expected[i];
    const std::optional<Hit> got = accel.intersect(oracle.rays[i]);
    const bool occluded = accel.occluded(oracle.rays[i]);
    EXPECT_TRUE(same_bits(got, expected))
        << label << ": ray " << i << " expected " << describe_hit(expected) << ", got " << describe_hit(got);
    EXPECT_EQ(occluded, expected.has_value()) << label << ": occluded() of ray " << i;
    if (!same_bits(got, expected) || occluded != expected.has_value()) return hits;
    hits += expected.has_value() ? 1 : 0;
  }
  return hits;
}

}  // namespace vf::test
