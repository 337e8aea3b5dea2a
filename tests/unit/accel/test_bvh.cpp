#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "support/same_hit.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/bvh_data.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"

namespace vf {
namespace {

using test::Triangle;

TEST(Bvh, ClosestHitsAreBitIdenticalToTheOracle) {
  // Bit-identical including ties and normals: the leaves use the oracle's kernel and the lowest-index rule.
  std::vector<Triangle> triangles = test::random_soup(21, 3000, 0.01f, 0.2f);
  for (int i = 0; i < 30; ++i) triangles[static_cast<std::size_t>(97 * i)] = triangles[7];
  const TriangleSet set = test::set_from_triangles(triangles);
  const Bvh bvh = Bvh::build(set);
  const BruteForce oracle = BruteForce::build(set);
  const std::vector<Ray> rays = test::random_rays(set, 5, 3000);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit expected = oracle.intersect(rays[i]);
    ASSERT_TRUE(test::same_bits(bvh.intersect(rays[i]), expected)) << "ray " << i;
    ASSERT_EQ(bvh.occluded(rays[i]), expected.found) << "ray " << i;
    hits += expected ? 1 : 0;
  }
  EXPECT_GT(hits, 300u);
}

TEST(Bvh, BuildDoesNotDependOnThreadCount) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(22, 60000, 0.001f, 0.05f));
  const std::vector<Ray> rays = test::random_rays(set, 6, 4000);
  const auto build_and_query = [&](int threads, AccelStats& stats) {
    const ThreadLimit limit(threads);
    const Bvh bvh = Bvh::build(set);
    stats = bvh.stats();
    std::vector<Hit> hits;
    for (const Ray& r : rays) hits.push_back(bvh.intersect(r));
    return hits;
  };
  AccelStats one{}, two{};
  const auto hits_one = build_and_query(1, one);
  const auto hits_two = build_and_query(2, two);
  EXPECT_EQ(one.node_count, two.node_count);
  EXPECT_EQ(one.leaf_count, two.leaf_count);
  EXPECT_EQ(one.max_depth, two.max_depth);
  EXPECT_EQ(one.memory_bytes, two.memory_bytes);
  for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_TRUE(test::same_bits(hits_one[i], hits_two[i])) << "ray " << i;
}

TEST(Bvh, StatsDescribeTheTree) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(23, 20000, 0.005f, 0.05f));
  const BvhConfig config;
  const Bvh bvh = Bvh::build(set, config);
  const AccelStats& s = bvh.stats();
  EXPECT_EQ(s.reference_count, set.size());
  EXPECT_GE(s.leaf_count, set.size() / static_cast<std::size_t>(config.max_leaf_size));
  EXPECT_GE(s.node_count, s.leaf_count / 8);
  EXPECT_LT(s.node_count, s.leaf_count);
  EXPECT_GE(s.max_depth, 4);  // 20000 triangles cannot fit in 8^3 leaves of at most 8
  EXPECT_LE(s.max_depth, 64);
  EXPECT_GE(s.memory_bytes, set.size() * (9 * sizeof(float) + 3 * sizeof(std::uint32_t)));
  EXPECT_EQ(Bvh::name(), "bvh");
}

TEST(Bvh, EmptyAndSingleTriangleSets) {
  const Bvh empty = Bvh::build(TriangleSet{});
  EXPECT_FALSE(empty.intersect(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_FALSE(empty.occluded(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_EQ(empty.stats().leaf_count, 0u);

  const Bvh one = Bvh::build(test::set_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}}));
  const Hit h = one.intersect(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}});
  ASSERT_TRUE(h);
  EXPECT_EQ(h.t, 2.0f);
  EXPECT_EQ(h.prim, 0u);
  EXPECT_EQ(h.instance, 0u);
  ASSERT_TRUE(h.has_normal);
  EXPECT_EQ(h.normal, (Vec3f{0, 0, 1}));  // cross(p1 - p0, p2 - p0)
  EXPECT_FALSE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, 0.0f, 1.99f}));
  EXPECT_TRUE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, 0.0f, 2.0f}));
  EXPECT_EQ(one.stats().max_depth, 1);
}

TEST(Bvh, CountingQueriesAnswerAsThePlainOnesAndCountTheirWork) {
  // One triangle: a direct Bvh, whose one block (one triangle) every query tests without a node.
  const Bvh one = Bvh::build(test::set_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}}));
  BvhQueryCounters c;
  EXPECT_TRUE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}}, c));
  EXPECT_EQ(c.rays, 1u);
  EXPECT_EQ(c.nodes, 0u);
  EXPECT_EQ(c.leaves, 1u);
  EXPECT_EQ(c.blocks, 1u);
  EXPECT_EQ(c.triangle_tests, 1u);
  EXPECT_FALSE(one.intersect(Ray{{5.0f, 5.0f, 2.0f}, {0, 0, -1}}, c));  // a miss tests the block too
  EXPECT_EQ(c.rays, 2u);
  EXPECT_EQ(c.nodes, 0u);
  EXPECT_EQ(c.leaves, 2u);

  const TriangleSet set = test::set_from_triangles(test::random_soup(24, 5000, 0.005f, 0.1f));
  const Bvh bvh = Bvh::build(set);
  const std::vector<Ray> rays = test::random_rays(set, 8, 2000);
  BvhQueryCounters closest, any;
  for (const Ray& r : rays) {
    ASSERT_TRUE(test::same_bits(bvh.intersect(r, closest), bvh.intersect(r)));
    ASSERT_EQ(bvh.occluded(r, any), bvh.occluded(r));
  }
  for (const BvhQueryCounters& k : {closest, any}) {
    EXPECT_EQ(k.rays, rays.size());
    EXPECT_GE(k.nodes, k.rays);  // every walk tests the root's children
    EXPECT_GE(k.blocks, k.leaves);
    EXPECT_LE(k.triangle_tests, 8 * k.blocks);
    EXPECT_GT(k.triangle_tests, 7 * k.blocks / 2);  // the build fills most blocks
  }
  EXPECT_LE(any.nodes, closest.nodes);  // any hit stops at the first occluder
  EXPECT_LT(any.triangle_tests, closest.triangle_tests);
}

TEST(Bvh, SmallSetsTestedWithoutNodesAnswerAsTheOracle) {
  // Sets of one or two blocks are queried without their nodes (kDirectBlocks); larger ones walk.
  // Both answer as brute force, ties included (a triangle repeated at a higher index), one ray at a
  // time and streamed.
  std::size_t direct_sets = 0, walked_sets = 0, hits = 0;
  for (std::size_t n = 1; n <= 24; ++n) {
    std::vector<Triangle> triangles = test::random_soup(300 + n, n, 0.2f, 0.5f);
    if (n > 3) triangles[n - 1] = triangles[1];
    const TriangleSet set = test::set_from_triangles(triangles);
    const Bvh bvh = Bvh::build(set);
    const BruteForce oracle = BruteForce::build(set);
    std::vector<Ray> rays = test::random_rays(set, 40 + n, 1000);
    for (std::size_t i = 0; i < rays.size(); i += 5) rays[i].tmax = 0.3f;
    std::vector<std::uint8_t> streamed(rays.size(), 7);
    std::vector<Hit> closest(rays.size());
    occluded_block(bvh, rays, streamed);
    intersect_batch(bvh, rays, std::span<Hit>(closest));
    BvhQueryCounters counters;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Hit expected = oracle.intersect(rays[i]);
      ASSERT_TRUE(test::same_bits(bvh.intersect(rays[i], counters), expected)) << n << " triangles, ray " << i;
      ASSERT_TRUE(test::same_bits(closest[i], expected)) << n << " triangles, ray " << i;
      ASSERT_EQ(bvh.occluded(rays[i]), expected.found) << n << " triangles, ray " << i;
      ASSERT_EQ(streamed[i], expected.found ? 1 : 0) << n << " triangles, ray " << i;
      hits += expected ? 1 : 0;
    }
    (counters.nodes == 0 ? direct_sets : walked_sets) += 1;
    if (counters.nodes == 0) {
      EXPECT_LE(counters.blocks, 2 * rays.size()) << n << " triangles";
    }
  }
  EXPECT_GE(direct_sets, 8u);  // at least every set of one block
  EXPECT_GE(walked_sets, 4u);
  EXPECT_GT(hits, 600u) << direct_sets << " " << walked_sets;
}

TEST(Bvh, StreamedQueriesAnswerAsOneRayAtATime) {
  // Several walks stepped in turn: each answer must land on its own ray whatever the order walks end in.
  const TriangleSet set = test::set_from_triangles(test::random_soup(25, 4000, 0.005f, 0.1f));
  const Bvh bvh = Bvh::build(set);
  std::vector<Ray> rays = test::random_rays(set, 9, 3001);
  for (std::size_t i = 0; i < rays.size(); i += 7) rays[i].tmax = rays[i].tmax * 0.01f;  // short ones end early
  std::size_t hits = 0;
  for (const std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{4}, std::size_t{5}, rays.size()}) {
    std::vector<std::uint8_t> block(count, 7), batch(count, 7);
    std::vector<Hit> closest(count, Hit::triangle(1.0f, 0.5f, 0.5f, 3, 4, Vec3f{1.0f}));
    const std::span<const Ray> some(rays.data(), count);
    occluded_block(bvh, some, block);
    occluded_batch(bvh, some, batch);
    intersect_batch(bvh, some, std::span<Hit>(closest));
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint8_t expected = bvh.occluded(rays[i]) ? 1 : 0;
      ASSERT_EQ(block[i], expected) << count << " rays, ray " << i;
      ASSERT_EQ(batch[i], expected) << count << " rays, ray " << i;
      ASSERT_TRUE(test::same_bits(closest[i], bvh.intersect(rays[i]))) << count << " rays, ray " << i;
      if (count == rays.size()) hits += expected;
    }
  }
  EXPECT_GT(hits, 300u);
  EXPECT_LT(hits, rays.size() - 300u);
  const Bvh empty = Bvh::build(TriangleSet{});
  std::vector<std::uint8_t> none(3, 7);
  occluded_block(empty, std::span<const Ray>(rays.data(), 3), none);
  EXPECT_EQ(none, (std::vector<std::uint8_t>{0, 0, 0}));
  std::vector<Hit> misses(3, Hit::triangle(1.0f, 0.5f, 0.5f, 3, 4, Vec3f{1.0f}));
  intersect_batch(empty, std::span<const Ray>(rays.data(), 3), std::span<Hit>(misses));
  for (const Hit& h : misses) EXPECT_FALSE(h);
}

TEST(Bvh, DepthStaysBoundedOnPathologicalInput) {
  // Triangles at geometrically shrinking scales invite a deep SAH tree; identical copies defeat
  // binning. Both must stay within the traversal stack and answer like the oracle.
  std::vector<Triangle> triangles;
  for (int i = 0; i < 3000; ++i) {
    const float s = std::ldexp(1.0f, -(i % 100));
    triangles.push_back({Vec3f{s, 0, 0}, Vec3f{s, s, 0.5f * s}, Vec3f{0, s, s}});
  }
  const Triangle same{Vec3f{0, 0, 2}, Vec3f{1, 0, 2}, Vec3f{0, 1, 2}};
  triangles.insert(triangles.end(), 2000, same);
  const TriangleSet set = test::set_from_triangles(triangles);
  const Bvh bvh = Bvh::build(set);
  EXPECT_LE(bvh.stats().max_depth, 64);
  const BruteForce oracle = BruteForce::build(set);
  const std::vector<Ray> rays = test::random_rays(set, 7, 1000);
  for (std::size_t i = 0; i < rays.size(); ++i)
    ASSERT_TRUE(test::same_bits(bvh.intersect(rays[i]), oracle.intersect(rays[i]))) << "ray " << i;
}

TEST(Bvh, RejectsBadConfig) {
  const TriangleSet set = test::set_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}});
  EXPECT_THROW(Bvh::build(set, BvhConfig{.bin_count = 1}), Error);
  EXPECT_THROW(Bvh::build(set, BvhConfig{.bin_count = 1000}), Error);
  EXPECT_THROW(Bvh::build(set, BvhConfig{.max_leaf_size = 0}), Error);
  EXPECT_THROW(Bvh::build(set, BvhConfig{.max_leaf_size = 100000}), Error);
  EXPECT_THROW(Bvh::build(set, BvhConfig{.intersection_cost = 0.0f}), Error);
}

}  // namespace
}  // namespace vf

namespace vf {
namespace {

// The tree as public data (bvh_data.hpp): every triangle in exactly one leaf, every child's box
// holding its leaf's triangles or its node's children's boxes, indices in range, leaves within the
// leaf size; empty for an empty set; the same tree whatever the thread count.
TEST(BvhData, EveryTriangleOnceInsideEveryBoxOnItsPath) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(31, 4000, 0.002f, 0.05f));
  const WideBvhData data = build_wide_bvh(set, {.max_leaf_size = 4}, 1);
  ASSERT_FALSE(data.nodes.empty());
  EXPECT_EQ(data.triangles.size(), set.size());
  std::vector<int> seen(set.size(), 0);
  const auto inside = [](const Bounds3f& outer, const Bounds3f& inner) {
    for (int a = 0; a < 3; ++a)
      if (!(outer.lo[a] <= inner.lo[a] && inner.hi[a] <= outer.hi[a])) return false;
    return true;
  };
  std::size_t leaves = 0;
  for (const WideBvhNode& node : data.nodes)
    for (const WideBvhChild& c : node.children) {
      if (c.kind == WideBvhChild::Kind::node) {
        ASSERT_LT(c.index, data.nodes.size());
        for (const WideBvhChild& grandchild : data.nodes[c.index].children) {
          if (grandchild.kind != WideBvhChild::Kind::empty) {
            EXPECT_TRUE(inside(c.bounds, grandchild.bounds));
          }
        }
      } else if (c.kind == WideBvhChild::Kind::leaf) {
        ++leaves;
        ASSERT_GE(c.count, 1u);
        ASSERT_LE(c.count, 4u);
        ASSERT_LE(c.index + c.count, data.triangles.size());
        for (std::uint32_t k = c.index; k < c.index + c.count; ++k) {
          const std::uint32_t t = data.triangles[k];
          ++seen[t];
          Bounds3f box;
          for (const Vec3f& p : set.triangles[t]) box.extend(p);
          EXPECT_TRUE(inside(c.bounds, box)) << t;
        }
      }
    }
  for (std::size_t t = 0; t < set.size(); ++t) ASSERT_EQ(seen[t], 1) << t;
  EXPECT_EQ(data.stats.leaf_count, leaves);
  EXPECT_TRUE(build_wide_bvh(TriangleSet{}).nodes.empty());
  EXPECT_THROW(build_wide_bvh(set, {.max_leaf_size = 17}), Error);
  // Thread independence: one thread builds the same nodes.
  const ThreadLimit one(1);
  const WideBvhData serial = build_wide_bvh(set, {.max_leaf_size = 4}, 1);
  ASSERT_EQ(serial.nodes.size(), data.nodes.size());
  EXPECT_EQ(serial.triangles, data.triangles);
}

}  // namespace
}  // namespace vf
