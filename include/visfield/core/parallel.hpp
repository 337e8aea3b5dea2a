#pragma once
/// \file Thread-count control and the parallel loops every module runs its work in: TBB's, or
/// under ThreadSanitizer the std::thread backend of parallel_threads.hpp (libtbb is not
/// instrumented, so TSan would report TBB's own task hand-offs as races).

#include <algorithm>
#include <iterator>
#include <memory>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#if defined(__SANITIZE_THREAD__)
#define VISFIELD_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define VISFIELD_TSAN 1
#endif
#endif

#include "visfield/core/interrupt.hpp"
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

/// Sorts [first, last) by operator<, in parallel, polling check_interrupt() every few milliseconds
/// of work (a signal throws vf::Interrupted and leaves the range in some permutation). The order of
/// equal elements depends only on the input, never on the thread count. O(n log n) work and one
/// temporary copy of the range.
template <class Iterator>
void parallel_sort(Iterator first, Iterator last) {
  using Value = typename std::iterator_traits<Iterator>::value_type;
  const std::size_t n = static_cast<std::size_t>(last - first);
  // Runs of a fixed length (not one per thread) keep the result independent of the thread count;
  // each is short enough to sort between two interrupt checks.
  constexpr std::size_t kRun = std::size_t{1} << 16;
  if (n <= kRun) {
    std::sort(first, last);
    return;
  }
  const std::size_t runs = (n + kRun - 1) / kRun;
  parallel_for(std::size_t{0}, runs, [&](std::size_t r) {
    check_interrupt();
    std::sort(first + r * kRun, first + std::min(n, (r + 1) * kRun));
  });
  std::vector<Value> buffer(n);
  bool in_buffer = false;
  for (std::size_t width = kRun; width < n; width *= 2) {
    const std::size_t pairs = (n + 2 * width - 1) / (2 * width);
    const auto merge_pairs = [&](auto from, auto to) {
      parallel_for(std::size_t{0}, pairs, [&](std::size_t p) {
        check_interrupt();
        const std::size_t lo = p * 2 * width, mid = std::min(n, lo + width), hi = std::min(n, lo + 2 * width);
        std::merge(std::make_move_iterator(from + lo), std::make_move_iterator(from + mid), std::make_move_iterator(from + mid),
                   std::make_move_iterator(from + hi), to + lo);
      });
    };
    if (in_buffer)
      merge_pairs(buffer.begin(), first);
    else
      merge_pairs(first, buffer.begin());
    in_buffer = !in_buffer;
  }
  if (in_buffer) std::move(buffer.begin(), buffer.end(), first);
}

}  // namespace vf
