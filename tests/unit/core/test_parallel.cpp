// The parallel loops: TBB's through vf::, and the std::thread backend that replaces them under
// ThreadSanitizer, held to the same contract (every index once, ordered reduction, exceptions).

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/blocked_range.h>

#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/parallel_threads.hpp"

namespace vf {
namespace {

using Range = tbb::blocked_range<std::size_t>;

/// The same checks against both backends.
struct Vf {
  template <class... A> static void for_(A&&... a) { vf::parallel_for(std::forward<A>(a)...); }
  template <class... A> static auto reduce(A&&... a) { return vf::parallel_reduce(std::forward<A>(a)...); }
  template <class... A> static void invoke(A&&... a) { vf::parallel_invoke(std::forward<A>(a)...); }
};
struct Threads {
  template <class... A> static void for_(A&&... a) { threads::parallel_for(std::forward<A>(a)...); }
  template <class... A> static auto reduce(A&&... a) { return threads::parallel_reduce(std::forward<A>(a)...); }
  template <class... A> static void invoke(A&&... a) { threads::parallel_invoke(std::forward<A>(a)...); }
};

template <class Backend>
class ParallelLoops : public ::testing::Test {};
using Backends = ::testing::Types<Vf, Threads>;
TYPED_TEST_SUITE(ParallelLoops, Backends);

TYPED_TEST(ParallelLoops, ForVisitsEveryIndexOnce) {
  ThreadLimit limit(4);
  std::vector<std::atomic<int>> visits(100'003);
  TypeParam::for_(Range(0, visits.size(), 7), [&](const Range& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) visits[i].fetch_add(1);
  });
  for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i].load(), 1) << i;
  std::vector<std::atomic<int>> indexed(1000);
  TypeParam::for_(std::size_t{0}, indexed.size(), [&](std::size_t i) { indexed[i].fetch_add(1); });
  for (std::size_t i = 0; i < indexed.size(); ++i) ASSERT_EQ(indexed[i].load(), 1) << i;
}

TYPED_TEST(ParallelLoops, FunctionalReduceKeepsOrderOfAnAssociativeReduction) {
  ThreadLimit limit(4);
  // String concatenation is associative but not commutative: any reordering shows.
  const std::string joined = TypeParam::reduce(
      Range(0, 2000, 3), std::string{},
      [](const Range& r, std::string s) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) s += static_cast<char>('a' + i % 26);
        return s;
      },
      [](std::string a, const std::string& b) { return a + b; });
  std::string expected;
  for (std::size_t i = 0; i < 2000; ++i) expected += static_cast<char>('a' + i % 26);
  EXPECT_EQ(joined, expected);
}

struct SumBody {
  const std::vector<std::uint64_t>& values;
  std::uint64_t sum = 0;
  explicit SumBody(const std::vector<std::uint64_t>& v) : values(v) {}
  SumBody(SumBody& o, tbb::split) : values(o.values) {}
  void operator()(const Range& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) sum += values[i];
  }
  void join(const SumBody& o) { sum += o.sum; }
};

TEST(ParallelLoops, BodyReduceSumsEveryElementOnceInBothBackends) {
  ThreadLimit limit(4);
  std::vector<std::uint64_t> values(50'000);
  std::iota(values.begin(), values.end(), std::uint64_t{1});
  SumBody tbb_body(values), thread_body(values);
  vf::parallel_reduce(Range(0, values.size(), 64), tbb_body);
  threads::parallel_reduce(Range(0, values.size(), 64), thread_body);
  const std::uint64_t expected = values.size() * (values.size() + 1) / 2;
  EXPECT_EQ(tbb_body.sum, expected);
  EXPECT_EQ(thread_body.sum, expected);
}

TYPED_TEST(ParallelLoops, NestedInvokeRunsBothSidesAndPropagatesExceptions) {
  ThreadLimit limit(2);
  std::atomic<int> leaves{0};
  // A binary recursion 10 deep: 1024 leaves, far more nested calls than the helper budget.
  auto recurse = [&](auto& self, int depth) -> void {
    if (depth == 0) {
      leaves.fetch_add(1);
      return;
    }
    TypeParam::invoke([&] { self(self, depth - 1); }, [&] { self(self, depth - 1); });
  };
  recurse(recurse, 10);
  EXPECT_EQ(leaves.load(), 1024);
  EXPECT_THROW(TypeParam::invoke([] {}, [] { throw std::runtime_error("task failed"); }), std::runtime_error);
  EXPECT_THROW(TypeParam::for_(std::size_t{0}, std::size_t{100},
                               [](std::size_t i) {
                                 if (i == 57) throw std::runtime_error("index 57");
                               }),
               std::runtime_error);
}

TEST(ParallelLoops, ThreadBackendUsesTheThreadLimit) {
  ThreadLimit limit(3);
  EXPECT_EQ(threads_in_force(), 3);
  std::mutex m;
  std::set<std::thread::id> seen;
  threads::parallel_for(Range(0, 3000, 1), [&](const Range&) {
    std::lock_guard lock(m);
    seen.insert(std::this_thread::get_id());
  });
  EXPECT_LE(seen.size(), 3u);
}

/// Ordered by key only, so that elements with equal keys but different payloads tie.
struct Keyed {
  std::uint32_t key, payload;
  bool operator<(const Keyed& o) const { return key < o.key; }
  bool operator==(const Keyed& o) const = default;
};

// Many ties: the sort may order equal keys any way it likes, but the same way for every thread
// count. Sizes straddle the run length and give odd numbers of merge rounds.
TEST(ParallelSort, SortsAPermutationTheSameWayForAnyThreadCount) {
  for (const std::size_t n : {std::size_t{0}, std::size_t{1000}, std::size_t{65536}, std::size_t{65537}, std::size_t{300001}}) {
    std::vector<Keyed> input(n);
    std::uint64_t state = 12345;
    for (std::size_t i = 0; i < n; ++i) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      input[i] = {static_cast<std::uint32_t>(state >> 52), static_cast<std::uint32_t>(i)};  // 4096 keys
    }
    std::vector<std::vector<Keyed>> results;
    for (const int threads : {1, 2, 5}) {
      ThreadLimit limit(threads);
      auto v = input;
      vf::parallel_sort(v.begin(), v.end());
      results.push_back(v);
    }
    EXPECT_TRUE(std::is_sorted(results[0].begin(), results[0].end())) << n;
    EXPECT_EQ(results[1], results[0]) << n;
    EXPECT_EQ(results[2], results[0]) << n;
    const auto full = [](const Keyed& a, const Keyed& b) { return a.key < b.key || (a.key == b.key && a.payload < b.payload); };
    auto permutation = results[0];
    std::sort(permutation.begin(), permutation.end(), full);
    std::sort(input.begin(), input.end(), full);
    EXPECT_EQ(permutation, input) << n;
  }
}

TEST(ParallelSort, ARecordedSignalStopsALargeSort) {
  std::vector<std::uint32_t> v(1 << 20);
  std::iota(v.rbegin(), v.rend(), 0u);
  request_interrupt(15);
  EXPECT_THROW(vf::parallel_sort(v.begin(), v.end()), Interrupted);
  clear_interrupt();
  vf::parallel_sort(v.begin(), v.end());
  EXPECT_TRUE(std::is_sorted(v.begin(), v.end()));
}

}  // namespace
}  // namespace vf
