#pragma once
/// \file Tracing the ray set through the structures: the timed work of visfield-bench.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "bench_accel.hpp"
#include "timing.hpp"
#include "visfield/accel/beam_field.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/render/ray_kind.hpp"

namespace vf::bench {

/// Answers of one structure for the whole ray set: `hits` for closest-hit kinds, `occluded` (1/0)
/// for occlusion kinds; the other vector stays empty.
struct QueryResults {
  std::vector<Hit> hits;
  std::vector<std::uint8_t> occluded;
};

/// One structure's run times and answers (identical in every run).
struct QueryMeasurement {
  Timings timings;
  QueryResults results;
};

/// Traces `rays` through each of `accels` (intersect for closest-hit kinds, occluded for occlusion
/// kinds) with intersect_batch / occluded_batch: the same TBB loop over chunks of rays for every
/// structure, under the caller's ThreadLimit. Warm-up and repetitions as `plan` says, the
/// repetitions interleaved across structures (time_interleaved). One measurement per structure.
/// `one_ray[i]` (when given) runs structure i one intersect()/occluded() a ray in the same loop instead.
std::vector<QueryMeasurement> measure_queries(std::span<const BenchAccel* const> accels, std::span<const Ray> rays,
                                              RayKind kind, const TimingPlan& plan, const std::vector<bool>& one_ray = {});

/// BeamField's work on `rays` (the queries `kind` asks, with counters on; untimed), or nothing when
/// `accel` is not a BeamField. Parallel; the sums do not depend on the thread count.
std::optional<BeamQueryCounters> count_beam_work(const BenchAccel& accel, std::span<const Ray> rays, RayKind kind);

/// The flattened Bvh's work on `rays` (node visits, leaves, blocks, triangle tests; untimed), or
/// nothing when `accel` is not one. Parallel; the sums do not depend on the thread count.
std::optional<BvhQueryCounters> count_bvh_work(const BenchAccel& accel, std::span<const Ray> rays, RayKind kind);

}  // namespace vf::bench
