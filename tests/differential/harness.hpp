#pragma once
/// \file Differential testing of exact structures against the BruteForce oracle. A structure plugs in
/// by being listed in exact_structures.hpp; the harness compares its closest hits and occlusion
/// answers ray by ray and prints the first mismatches with the ray in hexadecimal floats.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "visfield/accel/accelerator.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

/// How to compare and how much to print.
struct DiffOptions {
  double relative_t_tolerance = 1e-5;  ///< |t - t_oracle| above this times |t_oracle| is a mismatch.
  int max_reports = 5;                 ///< Mismatches printed (the first ones, by ray index).
  std::string label;                   ///< Printed with each mismatch (scene and ray set).
};

/// Counts of disagreements with the oracle over a ray set.
struct DiffReport {
  std::size_t rays = 0;
  std::size_t oracle_hits = 0;          ///< Rays the oracle reports a closest hit for.
  std::size_t oracle_occluded = 0;      ///< Rays the oracle reports occluded.
  std::size_t closest_mismatches = 0;   ///< Hit vs miss, t off, different triangle at a different t, or t out of range.
  std::size_t occluded_mismatches = 0;  ///< occluded() differs from the oracle.
};

/// The oracle's answers for one ray set, computed once and compared against any number of structures.
struct OracleAnswers {
  std::vector<std::optional<Hit>> closest;
  std::vector<std::uint8_t> occluded;
};

/// Runs the oracle over `rays` (parallel). Occlusion is by definition "a closest hit exists in
/// [tmin, tmax]"; with `query_occluded` the oracle's own occluded() is called as well and must agree
/// (its disagreements are counted as oracle_inconsistencies). Cost O(rays * triangles).
inline OracleAnswers oracle_answers(const BruteForce& oracle, std::span<const Ray> rays, bool query_occluded,
                                    std::size_t* oracle_inconsistencies = nullptr) {
  OracleAnswers answers;
  answers.closest.resize(rays.size());
  answers.occluded.resize(rays.size());
  std::vector<std::uint8_t> inconsistent(rays.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      answers.closest[i] = oracle.intersect(rays[i]);
      answers.occluded[i] = answers.closest[i].has_value() ? 1 : 0;
      if (query_occluded && oracle.occluded(rays[i]) != answers.closest[i].has_value()) inconsistent[i] = 1;
    }
  });
  if (oracle_inconsistencies) {
    *oracle_inconsistencies = 0;
    for (std::uint8_t x : inconsistent) *oracle_inconsistencies += x;
  }
  return answers;
}

namespace detail {

inline std::string describe(const std::optional<Hit>& h) {
  if (!h) return "miss";
  char buf[160];
  std::snprintf(buf, sizeof buf, "t=%a (%.9g) u=%.6g v=%.6g prim=%u instance=%u", h->t, h->t, h->u, h->v, h->prim,
                h->instance);
  return buf;
}

inline std::string describe(const Ray& r) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "org=(%a, %a, %a) dir=(%a, %a, %a) tmin=%a tmax=%a", r.org.x, r.org.y, r.org.z,
                r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
  return buf;
}

/// Why `got` disagrees with `expected` for `ray`, or nullptr when it does not.
inline const char* closest_mismatch(const Ray& ray, const std::optional<Hit>& expected, const std::optional<Hit>& got,
                                    double tolerance) {
  if (expected.has_value() != got.has_value()) return expected ? "missed a hit" : "reported a hit the oracle misses";
  if (!got) return nullptr;
  if (!(got->t >= ray.tmin && got->t <= ray.tmax)) return "t outside [tmin, tmax]";
  if (std::fabs(static_cast<double>(got->t) - expected->t) > tolerance * std::fabs(static_cast<double>(expected->t)))
    return "t differs";
  // Equal t on different triangles is a tie, which any triangle may win.
  if ((got->prim != expected->prim || got->instance != expected->instance) && got->t != expected->t)
    return "different triangle at a different t";
  return nullptr;
}

}  // namespace detail

/// Compares `accel` with precomputed oracle answers for the same rays; prints the first mismatches.
template <Accelerator A>
DiffReport compare_answers(const A& accel, std::span<const Ray> rays, const OracleAnswers& oracle,
                           const DiffOptions& options = {}) {
  std::vector<const char*> closest_why(rays.size(), nullptr);
  std::vector<std::optional<Hit>> got(rays.size());
  std::vector<std::uint8_t> occluded_wrong(rays.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 64), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      got[i] = accel.intersect(rays[i]);
      closest_why[i] = detail::closest_mismatch(rays[i], oracle.closest[i], got[i], options.relative_t_tolerance);
      occluded_wrong[i] = (accel.occluded(rays[i]) ? 1 : 0) != oracle.occluded[i] ? 1 : 0;
    }
  });
  DiffReport report;
  report.rays = rays.size();
  int printed = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    report.oracle_hits += oracle.closest[i].has_value() ? 1 : 0;
    report.oracle_occluded += oracle.occluded[i];
    if (!closest_why[i] && !occluded_wrong[i]) continue;
    report.closest_mismatches += closest_why[i] ? 1 : 0;
    report.occluded_mismatches += occluded_wrong[i];
    if (printed++ >= options.max_reports) continue;
    std::printf("[%s] %s mismatch on ray %zu: %s\n  ray    %s\n  oracle %s (occluded %d)\n  %-6s %s\n",
                options.label.c_str(), A::name().c_str(), i, closest_why[i] ? closest_why[i] : "occluded() differs",
                detail::describe(rays[i]).c_str(), detail::describe(oracle.closest[i]).c_str(), oracle.occluded[i],
                A::name().c_str(), detail::describe(got[i]).c_str());
  }
  return report;
}

/// Builds the structure with its defaults; specialise for structures that need more than a set.
template <class A>
A build_for_test(const TriangleSet& set) {
  return A::build(set);
}

/// Builds `A` and the oracle over `set` and compares them on `rays`.
template <Accelerator A>
DiffReport compare_with_oracle(const TriangleSet& set, std::span<const Ray> rays, const DiffOptions& options = {}) {
  const BruteForce oracle = BruteForce::build(set);
  const OracleAnswers answers = oracle_answers(oracle, rays, false);
  const A accel = build_for_test<A>(set);
  return compare_answers(accel, rays, answers, options);
}

}  // namespace vf::test
