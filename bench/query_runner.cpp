#include "query_runner.hpp"

#include <functional>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>

#include "visfield/accel/batch.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::bench {

std::vector<QueryMeasurement> measure_queries(std::span<const BenchAccel* const> accels, std::span<const Ray> rays,
                                              RayKind kind, const TimingPlan& plan, const std::vector<bool>& one_ray) {
  std::vector<QueryMeasurement> measurements(accels.size());
  std::vector<std::function<void()>> jobs;
  jobs.reserve(accels.size());
  for (std::size_t i = 0; i < accels.size(); ++i) {
    const BenchAccel& accel = *accels[i];
    QueryResults& results = measurements[i].results;
    const bool single = i < one_ray.size() && one_ray[i];
    // Result arrays are allocated here, outside the timed runs. With `single`, batch.hpp's generic
    // loop (one query a ray) is named explicitly, past the structure's own batch overload.
    if (is_occlusion_kind(kind)) {
      results.occluded.resize(rays.size());
      jobs.emplace_back([&accel, &results, rays, single] {
        visit_accel(accel, [&](const auto& structure) {
          using S = std::decay_t<decltype(structure)>;
          if constexpr (OcclusionQuery<S>) {
            if (single) return vf::occluded_batch<S>(structure, rays, std::span<std::uint8_t>(results.occluded));
          }
          occluded_batch(structure, rays, std::span<std::uint8_t>(results.occluded));
        });
      });
    } else {
      results.hits.resize(rays.size());
      jobs.emplace_back([&accel, &results, rays, single] {
        visit_accel(accel, [&](const auto& structure) {
          using S = std::decay_t<decltype(structure)>;
          if constexpr (ClosestHitQuery<S>) {
            if (single) return vf::intersect_batch<S>(structure, rays, std::span<Hit>(results.hits));
          }
          intersect_batch(structure, rays, std::span<Hit>(results.hits));
        });
      });
    }
  }
  std::vector<Timings> timings = time_interleaved(plan, jobs);
  for (std::size_t i = 0; i < accels.size(); ++i) measurements[i].timings = std::move(timings[i]);
  return measurements;
}

namespace {

/// The counters of `Structure`'s counting queries summed over `rays`, or nothing when `accel` holds
/// another structure. Parallel; the sums do not depend on the thread count.
template <class Structure, class Counters>
std::optional<Counters> count_work(const BenchAccel& accel, std::span<const Ray> rays, RayKind kind) {
  return visit_accel(accel, [&](const auto& structure) -> std::optional<Counters> {
    if constexpr (std::is_same_v<std::decay_t<decltype(structure)>, Structure>) {
      tbb::combinable<Counters> per_thread;
      vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 4096), [&](const auto& range) {
        Counters& counters = per_thread.local();
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          if (is_occlusion_kind(kind)) {
            structure.occluded(rays[i], counters);
          } else {
            structure.intersect(rays[i], counters);
          }
        }
      });
      Counters total;
      per_thread.combine_each([&](const Counters& c) { total += c; });
      return total;
    } else {
      return std::nullopt;
    }
  });
}

}  // namespace

std::optional<BeamQueryCounters> count_beam_work(const BenchAccel& accel, std::span<const Ray> rays, RayKind kind) {
  return count_work<BeamField, BeamQueryCounters>(accel, rays, kind);
}

std::optional<BvhQueryCounters> count_bvh_work(const BenchAccel& accel, std::span<const Ray> rays, RayKind kind) {
  return count_work<Bvh, BvhQueryCounters>(accel, rays, kind);
}

}  // namespace vf::bench
