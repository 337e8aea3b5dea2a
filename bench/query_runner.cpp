#include "query_runner.hpp"

#include <functional>

#include "visfield/accel/batch.hpp"

namespace vf::bench {

std::vector<QueryMeasurement> measure_queries(std::span<const BenchAccel* const> accels, std::span<const Ray> rays,
                                              RayKind kind, const TimingPlan& plan) {
  std::vector<QueryMeasurement> measurements(accels.size());
  std::vector<std::function<void()>> jobs;
  jobs.reserve(accels.size());
  for (std::size_t i = 0; i < accels.size(); ++i) {
    const BenchAccel& accel = *accels[i];
    QueryResults& results = measurements[i].results;
    // Result arrays are allocated here, outside the timed runs.
    if (is_occlusion_kind(kind)) {
      results.occluded.resize(rays.size());
      jobs.emplace_back([&accel, &results, rays] {
        visit_accel(accel, [&](const auto& structure) {
          occluded_batch(structure, rays, std::span<std::uint8_t>(results.occluded));
        });
      });
    } else {
      results.hits.resize(rays.size());
      jobs.emplace_back([&accel, &results, rays] {
        visit_accel(accel,
                    [&](const auto& structure) { intersect_batch(structure, rays, std::span<Hit>(results.hits)); });
      });
    }
  }
  std::vector<Timings> timings = time_interleaved(plan, jobs);
  for (std::size_t i = 0; i < accels.size(); ++i) measurements[i].timings = std::move(timings[i]);
  return measurements;
}

}  // namespace vf::bench
