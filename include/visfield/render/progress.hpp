#pragma once
/// \file A progress bar on stderr for long jobs; thread-safe ticks.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>

#include "visfield/core/stopwatch.hpp"

namespace vf {

/// Prints "label [=====>    ] 42%" on stderr, only once the job has run for over `delay_s`
/// seconds and only when enabled; tick() is thread-safe and cheap (an atomic add).
class ProgressBar {
 public:
  /// A bar for a job of `total` units; prints nothing unless `enabled` and the job outlives `delay_s`.
  ProgressBar(std::string label, std::size_t total, bool enabled, double delay_s = 1.0);
  /// Calls finish().
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// Records `n` more units done; redraws at most ~10 times a second.
  void tick(std::size_t n = 1);
  /// Draws 100% (if the bar was shown) and ends the line; later calls do nothing. Call from one thread.
  void finish();

 private:
  void draw(std::size_t done);
  std::string label_;
  std::size_t total_;
  bool enabled_;
  double delay_s_;
  Stopwatch watch_;
  std::atomic<std::size_t> done_{0};
  std::atomic<std::int64_t> last_draw_ms_{-1000};
  std::atomic<bool> shown_{false}, finished_{false};
};

}  // namespace vf
