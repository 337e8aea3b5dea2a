#pragma once
/// \file The one wall-clock timer: every build time, render time and benchmark figure is taken with it.

#include <chrono>
#include <utility>

namespace vf {

/// Measures wall-clock time (steady clock) since construction. Cheap to copy; not shared between threads.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  /// Milliseconds since the start.
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  /// Seconds since the start.
  double elapsed_s() const { return elapsed_ms() * 1e-3; }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// Wall-clock milliseconds taken by one call of `fn`.
template <class F>
double time_ms(F&& fn) {
  const Stopwatch watch;
  std::forward<F>(fn)();
  return watch.elapsed_ms();
}

}  // namespace vf
