#include "timing.hpp"

#include "visfield/core/statistics.hpp"
#include "visfield/core/stopwatch.hpp"

namespace vf::bench {

double Timings::median_ms() const { return median(run_ms); }

Timings time_runs(const TimingPlan& plan, const std::function<void()>& job) {
  return time_interleaved(plan, std::span<const std::function<void()>>(&job, 1)).front();
}

Timings time_runs_measured(const TimingPlan& plan, const std::function<double()>& measured_job) {
  for (int i = 0; i < plan.warmup; ++i) (void)measured_job();
  Timings t;
  t.run_ms.reserve(static_cast<std::size_t>(plan.reps));
  for (int round = 0; round < plan.reps; ++round) t.run_ms.push_back(measured_job());
  return t;
}

std::vector<Timings> time_interleaved(const TimingPlan& plan, std::span<const std::function<void()>> jobs) {
  for (const auto& job : jobs) {
    for (int i = 0; i < plan.warmup; ++i) job();
  }
  std::vector<Timings> timings(jobs.size());
  for (Timings& t : timings) t.run_ms.reserve(static_cast<std::size_t>(plan.reps));
  for (int round = 0; round < plan.reps; ++round) {
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      timings[j].run_ms.push_back(time_ms(jobs[j]));
    }
  }
  return timings;
}

}  // namespace vf::bench
