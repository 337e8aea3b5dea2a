#pragma once
/// \file Warm-up, repetitions, median: how every timed figure of visfield-bench is taken.

#include <functional>
#include <span>
#include <vector>

namespace vf::bench {

/// How many times to run a job: `warmup` untimed runs, then `reps` (>= 1) timed ones.
struct TimingPlan {
  int warmup = 1;
  int reps = 5;
};

/// Wall-clock times of the timed runs, in milliseconds, in run order.
struct Timings {
  std::vector<double> run_ms;
  /// Median of run_ms (mean of the middle two for an even count); 0 when empty.
  double median_ms() const;
};

/// Runs `job` plan.warmup times untimed, then plan.reps times timed (steady clock).
Timings time_runs(const TimingPlan& plan, const std::function<void()>& job);

/// As time_runs, but each run's milliseconds are what `measured_job` returns: its own clock (the
/// GPU's CUDA events, say, which leave out host work and copies).
Timings time_runs_measured(const TimingPlan& plan, const std::function<double()>& measured_job);

/// Times several jobs against each other: each runs plan.warmup times untimed, then plan.reps
/// rounds run every job once, timed, in order. Interleaving the rounds spreads a change of machine
/// load over all jobs alike, so their ratios stay meaningful on a busy machine. One Timings per job.
std::vector<Timings> time_interleaved(const TimingPlan& plan, std::span<const std::function<void()>> jobs);

}  // namespace vf::bench
