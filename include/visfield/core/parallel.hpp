#pragma once
/// \file Thread-count control and the parallel loops every module runs its work in: TBB's, or
/// under ThreadSanitizer the std::thread backend of parallel_threads.hpp (libtbb is not
/// instrumented, so TSan would report TBB's own task hand-offs as races).

#include <algorithm>
#include <memory>
#include <utility>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#if defined(__SANITIZE_THREAD__)
#define VISFIELD_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define VISFIELD_TSAN 1
#endif
#endif

#include "visfield/core/parallel_threads.hpp"

#if defined(VISFIELD_TSAN)
namespace vf::parallel_backend {
using namespace vf::threads;
}
#else
namespace vf::parallel_backend {
using tbb::parallel_for;
using tbb::parallel_invoke;
using tbb::parallel_reduce;
}  // namespace vf::parallel_backend
#endif

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

/// tbb::parallel_for(range, body): body(subrange) for disjoint subranges covering `range`.
template <class Range, class Body>
void parallel_for(const Range& range, const Body& body) {
  parallel_backend::parallel_for(range, body);
}

/// tbb::parallel_for(first, last, f): f(i) for every i in [first, last).
template <class Index, class Func>
void parallel_for(Index first, Index last, const Func& f) {
  parallel_backend::parallel_for(first, last, f);
}

/// tbb::parallel_invoke(a, b): runs a() and b(), perhaps at the same time.
template <class A, class B>
void parallel_invoke(const A& a, const B& b) {
  parallel_backend::parallel_invoke(a, b);
}

/// tbb::parallel_reduce(range, identity, func, reduce) (the functional form); `reduce` must be
/// associative.
template <class Range, class Value, class Func, class Reduce>
Value parallel_reduce(const Range& range, const Value& identity, const Func& func, const Reduce& reduce) {
  return parallel_backend::parallel_reduce(range, identity, func, reduce);
}

/// tbb::parallel_reduce(range, body) (the imperative form): Body has operator()(const Range&),
/// a splitting constructor Body(Body&, tbb::split) and join(Body&). `body` holds the result.
template <class Range, class Body>
void parallel_reduce(const Range& range, Body& body) {
  parallel_backend::parallel_reduce(range, body);
}

/// Sorts [first, last) by operator<, in parallel (serially under TSan: std::sort).
template <class Iterator>
void parallel_sort(Iterator first, Iterator last) {
#if defined(VISFIELD_TSAN)
  std::sort(first, last);
#else
  tbb::parallel_sort(first, last);
#endif
}

}  // namespace vf
