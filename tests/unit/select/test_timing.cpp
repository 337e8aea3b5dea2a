#include <gtest/gtest.h>

#include "visfield/accel/brute_force.hpp"
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

TEST(Timing, MedianOfOddAndEvenCounts) {
  EXPECT_EQ(median({}), 0.0);
  EXPECT_EQ(median({3.0}), 3.0);
  EXPECT_EQ(median({5.0, 1.0, 4.0}), 4.0);
  EXPECT_EQ(median({5.0, 1.0, 4.0, 2.0}), 3.0);
}

TEST(Timing, TraceQueriesAnswersEveryQuery) {
  const Scene scene = make_builtin_scene("cornell", {.size = 100});
  const TriangleSet triangles = flatten(scene);
  const BruteForce brute = BruteForce::build(triangles);
  const QuerySet q = make_queries(RayKind::path, brute, scene, triangles, 600, 1, 2);
  std::uint64_t expected = 0;
  for (const Ray& ray : q.closest) {
    const auto hit = brute.intersect(ray);
    expected += hit ? hit->prim + 1 : 0;
  }
  for (const Ray& ray : q.shadow) expected += brute.occluded(ray) ? 1 : 0;
  EXPECT_EQ(trace_queries(brute, q), expected);
  EXPECT_EQ(median_batch_query_us(brute, QuerySet{}, 4, 2), 0.0);
  EXPECT_GE(median_batch_query_us(brute, q, 4, 2), 0.0);
  EXPECT_GE(large_set_query_us(brute, q, 1), 0.0);
  EXPECT_EQ(sample_query_us(brute, QuerySet{}, 1), 0.0);
  EXPECT_GE(sample_query_us(brute, q, 3), 0.0);
  const QuerySet middle = query_parts(q, 1, 4, 5);
  EXPECT_EQ(middle.closest.size(), q.closest.size() * 4 / 5 - q.closest.size() / 5);
}

TEST(Timing, TimedBuildKeepsTheLastStructure) {
  int calls = 0;
  const auto built = timed_build([&] { return ++calls; }, 3);
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(built.structure, 3);
  EXPECT_GE(built.build_ms, 0.0);
  EXPECT_EQ(timed_build([&] { return ++calls; }, 0).structure, 4);  // at least one build
}

}  // namespace
}  // namespace vf
