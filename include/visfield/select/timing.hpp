#pragma once
/// \file Wall-clock timing of builds and query sets, as medians of repetitions or batches (the machines are noisy).

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "visfield/accel/batch.hpp"
#include "visfield/accel/query.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/render/ray_kind.hpp"
#include "visfield/select/query_set.hpp"

namespace vf {

/// Keeps `value` observable so the computation producing it is not removed.
void do_not_optimize(std::uint64_t value);

/// A structure built `repetitions` (>= 1) times; keeps the last one and the median of the build times
/// the builds reported (stats().build_ms), in milliseconds.
template <class Structure>
struct TimedBuild {
  Structure structure;
  double build_ms = 0.0;
};

/// Calls `build()` `repetitions` times (at least once), each time freeing the previous structure
/// first; returns the last structure and the median of their stats().build_ms.
template <class Build>
auto timed_build(Build&& build, int repetitions) -> TimedBuild<decltype(build())> {
  using Structure = decltype(build());
  std::vector<double> times;
  std::optional<Structure> last;
  for (int r = 0; r < std::max(repetitions, 1); ++r) {
    last.reset();
    last.emplace(build());
    times.push_back(last->stats().build_ms);
  }
  return {std::move(*last), median(std::move(times))};
}

/// Parts [first, last) of `queries` cut into `parts` equal parts (closest and shadow queries each cut
/// evenly, so with path-major sets a part holds about the same whole paths of both). first <= last <= parts.
QuerySet query_parts(const QuerySet& queries, std::size_t first, std::size_t last, std::size_t parts);

/// Traces every query of `queries` through `accel` on the calling thread, closest-hit queries first;
/// returns a checksum of the answers (so no query can be optimised away).
template <Accelerator A>
std::uint64_t trace_queries(const A& accel, const QuerySet& queries) {
  std::uint64_t checksum = 0;
  for (const Ray& ray : queries.closest) {
    const Hit hit = accel.intersect(ray);
    checksum += hit ? hit.prim + 1 : 0;
  }
  for (const Ray& ray : queries.shadow) checksum += accel.occluded(ray) ? 1 : 0;
  return checksum;
}

/// Queries per timed batch of a large query set (about a millisecond of work).
inline constexpr std::size_t kTimingBatchQueries = 1024;

/// Per-query time in microseconds of tracing `queries` through `accel` as a workload does, each query
/// once, with `threads` threads: the set is cut into `parts` (>= 2) equal batches traced in order on
/// the calling thread; the first is untimed (it loads the structure's top levels into cache), every
/// other one is timed once; the median of their per-query times, divided by `threads` (>= 1).
///
/// Why this way: rays are independent, so a workload on T threads takes 1/T of the single-thread time;
/// timing small parallel batches instead would also time waking TBB's sleeping workers, which doubles
/// the apparent cost of a few hundred rays (the decision algorithm's sample) but not of a large set,
/// and would bias every estimate. The median drops batches during which the operating system ran
/// another process. Tracing the same rays twice is avoided because the second pass finds their cells
/// and triangles in cache (as little as half the time). 0 for an empty set.
template <Accelerator A>
double median_batch_query_us(const A& accel, const QuerySet& queries, std::size_t parts, int threads) {
  parts = std::max<std::size_t>(parts, 2);
  std::vector<double> times;
  std::uint64_t checksum = 0;
  for (std::size_t p = 0; p < parts; ++p) {
    const QuerySet part = query_parts(queries, p, p + 1, parts);
    if (part.size() == 0) continue;
    const double ms = time_ms([&] { checksum += trace_queries(accel, part); });
    if (p > 0) times.push_back(ms * 1000.0 / static_cast<double>(part.size()));
  }
  do_not_optimize(checksum);
  return median(std::move(times)) / static_cast<double>(std::max(threads, 1));
}

/// median_batch_query_us over batches of about kTimingBatchQueries queries (at least 2 batches): the
/// per-ray time of a large set such as the calibration's M rays.
template <Accelerator A>
double large_set_query_us(const A& accel, const QuerySet& queries, int threads) {
  return median_batch_query_us(accel, queries, queries.size() / kTimingBatchQueries + 1, threads);
}

/// Timed passes of a large ray set through a structure (after one untimed pass): their median counts.
inline constexpr int kTimedPasses = 3;

/// Per-query time in microseconds of `queries` through `accel` as batches on the threads in force
/// (intersect_batch for the closest-hit queries, occluded_batch for the others): one untimed pass, then
/// `passes` (>= 1) timed passes, the median. How the planner's candidates are measured, and its
/// profile's samples with them (a few thousand rays want more passes: each is a fraction of a
/// millisecond). -1 for an empty set.
template <class A>
double batch_passes_query_us(const A& accel, const QuerySet& queries, int passes = kTimedPasses) {
  if (queries.size() == 0) return -1.0;
  std::vector<Hit> hits(queries.closest.size());
  std::vector<std::uint8_t> occluded(queries.shadow.size());
  std::vector<double> times;
  for (int pass = 0; pass <= std::max(passes, 1); ++pass) {
    const double ms = time_ms([&] {
      if (!queries.closest.empty()) intersect_batch(accel, std::span<const Ray>(queries.closest), std::span<Hit>(hits));
      if (!queries.shadow.empty()) occluded_batch(accel, std::span<const Ray>(queries.shadow), std::span<std::uint8_t>(occluded));
    });
    if (pass > 0) times.push_back(ms);
  }
  return median(std::move(times)) * 1000.0 / static_cast<double>(queries.size());
}

/// Batches of the decision algorithm's sample: one untimed, four timed (S = 500 gives batches of 100).
inline constexpr std::size_t kSampleParts = 5;

/// The decision algorithm's per-ray time of a small sample: median_batch_query_us with kSampleParts.
template <Accelerator A>
double sample_query_us(const A& accel, const QuerySet& sample, int threads) {
  return median_batch_query_us(accel, sample, kSampleParts, threads);
}

}  // namespace vf
