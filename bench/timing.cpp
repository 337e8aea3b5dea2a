#include "timing.hpp"

#include <algorithm>
#include <chrono>

namespace vf::bench {

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

double Timings::median_ms() const { return median(run_ms); }

Timings time_runs(const TimingPlan& plan, const std::function<void()>& job) {
  return time_interleaved(plan, std::span<const std::function<void()>>(&job, 1)).front();
}

std::vector<Timings> time_interleaved(const TimingPlan& plan, std::span<const std::function<void()>> jobs) {
  for (const auto& job : jobs) {
    for (int i = 0; i < plan.warmup; ++i) job();
  }
  std::vector<Timings> timings(jobs.size());
  for (Timings& t : timings) t.run_ms.reserve(static_cast<std::size_t>(plan.reps));
  for (int round = 0; round < plan.reps; ++round) {
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      const auto start = std::chrono::steady_clock::now();
      jobs[j]();
      timings[j].run_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
  }
  return timings;
}

}  // namespace vf::bench
