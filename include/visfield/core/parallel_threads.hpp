#pragma once
/// \file A fork-join backend on std::thread with TBB's loop semantics, used in place of TBB under
/// ThreadSanitizer. Debian's libtbb is not instrumented, so TSan cannot see the ordering its
/// scheduler guarantees and reports races inside TBB's own inlined task code; threads started and
/// joined here are seen by TSan's interceptors, so what it reports is about our loop bodies.
/// Not tuned for speed: it splits a range into all its leaf pieces up front.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>

namespace vf {

/// The thread count in force: the ThreadLimit of the command (through tbb::global_control), else
/// all hardware threads. Thread-safe.
inline int threads_in_force() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

}  // namespace vf

namespace vf::threads {

/// Threads alive in this backend beyond the callers', across nested calls; past kMaxHelpers
/// nested work runs on the calling thread.
inline std::atomic<int> live_helpers{0};
inline constexpr int kMaxHelpers = 64;

/// Runs worker(k) for k in [0, n): k = 0 on the caller, the rest on new threads when the helper
/// budget allows, else on the caller after worker(0). Rethrows the first exception after all end.
template <class Worker>
void run_workers(int n, const Worker& worker) {
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto guarded = [&](int k) {
    try {
      worker(k);
    } catch (...) {
      std::lock_guard lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  };
  std::vector<std::thread> helpers;
  std::vector<int> inline_workers;
  for (int k = 1; k < n; ++k) {
    if (live_helpers.fetch_add(1) < kMaxHelpers) {
      helpers.emplace_back(guarded, k);
    } else {
      live_helpers.fetch_sub(1);
      inline_workers.push_back(k);
    }
  }
  guarded(0);
  for (int k : inline_workers) guarded(k);
  for (std::thread& t : helpers) {
    t.join();
    live_helpers.fetch_sub(1);
  }
  if (failure) std::rethrow_exception(failure);
}

/// `range` split as TBB would split it with grain-size limits, into indivisible pieces in order.
template <class Range>
std::vector<Range> leaf_pieces(const Range& range) {
  std::vector<Range> done;
  std::vector<Range> todo{range};
  while (!todo.empty()) {
    Range r = todo.back();
    todo.pop_back();
    if (!r.is_divisible()) {
      done.push_back(r);
      continue;
    }
    Range right(r, tbb::split{});
    todo.push_back(right);  // popped after `r`'s pieces, keeping the pieces in order
    todo.push_back(r);
  }
  return done;
}

/// Calls piece_work(worker, piece index) for every piece, pieces handed out dynamically.
template <class Work>
void for_each_piece(std::size_t pieces, int workers, const Work& piece_work) {
  std::atomic<std::size_t> next{0};
  run_workers(workers, [&](int worker) {
    for (std::size_t i = next.fetch_add(1); i < pieces; i = next.fetch_add(1)) piece_work(worker, i);
  });
}

inline int workers_for(std::size_t pieces) {
  return static_cast<int>(std::min<std::size_t>(pieces, static_cast<std::size_t>(std::max(1, threads_in_force()))));
}

/// As tbb::parallel_for(range, body).
template <class Range, class Body>
void parallel_for(const Range& range, const Body& body) {
  const std::vector<Range> pieces = leaf_pieces(range);
  for_each_piece(pieces.size(), workers_for(pieces.size()), [&](int, std::size_t i) { body(pieces[i]); });
}

/// As tbb::parallel_for(first, last, f).
template <class Index, class Func>
void parallel_for(Index first, Index last, const Func& f) {
  threads::parallel_for(tbb::blocked_range<Index>(first, last), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) f(i);
  });
}

/// As tbb::parallel_invoke(a, b).
template <class A, class B>
void parallel_invoke(const A& a, const B& b) {
  run_workers(2, [&](int k) { k == 0 ? a() : b(); });
}

/// As tbb::parallel_reduce(range, identity, func, reduce); pieces are reduced left to right.
template <class Range, class Value, class Func, class Reduce>
Value parallel_reduce(const Range& range, const Value& identity, const Func& func, const Reduce& reduce) {
  const std::vector<Range> pieces = leaf_pieces(range);
  std::vector<Value> partial(pieces.size(), identity);
  for_each_piece(pieces.size(), workers_for(pieces.size()),
                 [&](int, std::size_t i) { partial[i] = func(pieces[i], identity); });
  Value result = identity;
  for (Value& v : partial) result = reduce(std::move(result), std::move(v));
  return result;
}

/// As tbb::parallel_reduce(range, body): one body per worker, joined into `body` in worker order.
template <class Range, class Body>
void parallel_reduce(const Range& range, Body& body) {
  const std::vector<Range> pieces = leaf_pieces(range);
  const int workers = workers_for(pieces.size());
  std::vector<std::unique_ptr<Body>> split_bodies;
  for (int k = 1; k < workers; ++k) split_bodies.push_back(std::make_unique<Body>(body, tbb::split{}));
  for_each_piece(pieces.size(), workers, [&](int worker, std::size_t i) {
    Body& b = worker == 0 ? body : *split_bodies[static_cast<std::size_t>(worker - 1)];
    b(pieces[i]);
  });
  for (auto& b : split_bodies) body.join(*b);
}

}  // namespace vf::threads
