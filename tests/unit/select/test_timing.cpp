#include <gtest/gtest.h>

#include "visfield/accel/brute_force.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/scenes/builtin.hpp"
#include "visfield/select/timing.hpp"
#include "visfield/select/workload.hpp"

namespace vf {
namespace {

QuerySet numbered_queries(std::size_t closest, std::size_t shadow) {
  QuerySet q;
  for (std::size_t i = 0; i < closest; ++i) q.closest.push_back(Ray{Vec3f(static_cast<float>(i)), Vec3f(1.0f), 0.0f, 1.0f});
  for (std::size_t i = 0; i < shadow; ++i) q.shadow.push_back(Ray{Vec3f(-static_cast<float>(i)), Vec3f(1.0f), 0.0f, 1.0f});
  return q;
}

TEST(Timing, PartsCoverTheSetInOrderWithoutOverlap) {
  const QuerySet q = numbered_queries(103, 41);
  QuerySet joined;
  for (std::size_t p = 0; p < 5; ++p) {
    const QuerySet part = query_parts(q, p, p + 1, 5);
    EXPECT_GE(part.closest.size(), 20u);
    EXPECT_LE(part.closest.size(), 21u);
    joined.closest.insert(joined.closest.end(), part.closest.begin(), part.closest.end());
    joined.shadow.insert(joined.shadow.end(), part.shadow.begin(), part.shadow.end());
  }
  ASSERT_EQ(joined.closest.size(), 103u);
  ASSERT_EQ(joined.shadow.size(), 41u);
  for (std::size_t i = 0; i < 103; ++i) EXPECT_EQ(joined.closest[i].org.x, static_cast<float>(i));
  for (std::size_t i = 0; i < 41; ++i) EXPECT_EQ(joined.shadow[i].org.x, -static_cast<float>(i));
}

TEST(Timing, TraceQueriesAnswersEveryQuery) {
  const Scene scene = make_builtin_scene("cornell", {.size = 100});
  const TriangleSet triangles = flatten(scene);
  const BruteForce brute = BruteForce::build(triangles);
  const QuerySet q = make_queries(RayKind::path, brute, scene, triangles.bounds, 600, 1, 2);
  std::uint64_t expected = 0;
  for (const Ray& ray : q.closest) {
    const Hit hit = brute.intersect(ray);
    expected += hit ? hit.prim + 1 : 0;
  }
  for (const Ray& ray : q.shadow) expected += brute.occluded(ray) ? 1 : 0;
  EXPECT_EQ(trace_queries(brute, q), expected);
  EXPECT_EQ(median_batch_query_us(brute, QuerySet{}, 4, 2), 0.0);
  EXPECT_EQ(sample_query_us(brute, QuerySet{}, 1), 0.0);
  const QuerySet middle = query_parts(q, 1, 4, 5);
  EXPECT_EQ(middle.closest.size(), q.closest.size() * 4 / 5 - q.closest.size() / 5);
}

// A "structure" whose queries take a known time (a busy wait) and whose builds report known times.
class SlowStructure {
 public:
  explicit SlowStructure(double query_us, double build_ms = 0.0) : query_us_(query_us) { stats_.build_ms = build_ms; }
  Hit intersect(const Ray&) const {
    wait();
    return Hit{};
  }
  bool occluded(const Ray&) const {
    wait();
    return false;
  }
  const AccelStats& stats() const { return stats_; }
  static std::string name() { return "slow"; }
  static constexpr Exactness exactness = Exactness::exact;

 private:
  void wait() const {
    const Stopwatch watch;
    while (watch.elapsed_ms() * 1000.0 < query_us_) {
    }
  }
  double query_us_;
  AccelStats stats_;
};

TEST(Timing, PerQueryTimesAreAtLeastWhatTheQueriesTake) {
  // Each query takes at least 20 us on one thread; on T threads a workload takes 1/T of that.
  const SlowStructure slow(20.0);
  const QuerySet q = numbered_queries(60, 40);
  EXPECT_GE(median_batch_query_us(slow, q, 4, 1), 20.0);
  EXPECT_GE(sample_query_us(slow, q, 2), 10.0);
  EXPECT_GE(large_set_query_us(slow, q, 1), 20.0);
}

TEST(Timing, TimedBuildKeepsTheLastStructureAndTheMedianReportedTime) {
  int calls = 0;
  const auto built = timed_build([&] { return SlowStructure(0.0, 10.0 * ++calls); }, 3);  // 10, 20, 30 ms
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(built.structure.stats().build_ms, 30.0);
  EXPECT_EQ(built.build_ms, 20.0);
  EXPECT_EQ(timed_build([&] { return SlowStructure(0.0, 10.0 * ++calls); }, 0).build_ms, 40.0);  // at least one build
}

}  // namespace
}  // namespace vf
