#pragma once
/// \file Thread-count control for TBB.

#include <memory>

namespace vf {

/// While alive, limits TBB to `threads` worker threads (0 = all hardware threads). Create one per
/// command, on the main thread, before any parallel work.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;
  /// The number of threads in force.
  int threads() const { return threads_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int threads_ = 1;
};

/// Hardware threads available to this process.
int hardware_threads();

}  // namespace vf
