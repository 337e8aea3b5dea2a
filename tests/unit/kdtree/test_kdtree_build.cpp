// The SAH kd-tree build: the event sweep finds the plane a brute-force SAH evaluation finds, node
// splits keep every reference with its clipped bounds, and the trees are deterministic.

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "kdtree/kd_nodes.hpp"
#include "kdtree/sah_events.hpp"
#include "support/same_hit.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/median_bsp.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"

namespace vf {
namespace {

using test::Triangle;

/// Bounds of each node-local triangle, read from the node's events.
std::vector<Bounds3f> bounds_from_events(const kd::SahNode& node) {
  std::vector<Bounds3f> bounds(node.size());
  for (int axis = 0; axis < 3; ++axis)
    for (const kd::Event& e : node.events[axis]) {
      if (e.type() != kd::EventType::end) bounds[e.triangle()].lo[axis] = e.position;
      if (e.type() != kd::EventType::start) bounds[e.triangle()].hi[axis] = e.position;
    }
  return bounds;
}

/// The minimum SAH cost over every candidate plane (each triangle bound on each axis, planar
/// triangles tried on both sides), counting the triangles on each side directly: O(n^2).
double brute_force_best_cost(const kd::SahNode& node, const KdTreeConfig& config) {
  const std::vector<Bounds3f> bounds = bounds_from_events(node);
  double best = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis)
    for (const Bounds3f& candidate : bounds)
      for (const float p : {candidate.lo[axis], candidate.hi[axis]}) {
        std::size_t below = 0, above = 0, planar = 0;
        for (const Bounds3f& b : bounds) {
          if (b.lo[axis] == p && b.hi[axis] == p) {
            ++planar;
            continue;
          }
          below += b.lo[axis] < p ? 1 : 0;
          above += b.hi[axis] > p ? 1 : 0;
        }
        const kd::SplitCost cost_of(node.box, axis, node.size(), config);
        best = std::min({best, cost_of(p, below + planar, above), cost_of(p, below, above + planar)});
      }
  return best;
}

/// A small soup with axis-aligned triangles sharing coordinates, so that planar events and equal
/// positions occur.
std::vector<Triangle> small_mixed_soup(std::uint64_t seed) {
  std::vector<Triangle> triangles = test::random_soup(seed, 40, 0.02f, 0.4f);
  for (int i = 0; i < 6; ++i) {
    const float z = 0.25f * static_cast<float>(i % 3);
    triangles.push_back({Vec3f{0.1f * i, 0.1f, z}, Vec3f{0.1f * i + 0.3f, 0.2f, z}, Vec3f{0.1f * i, 0.5f, z}});
    triangles.push_back({Vec3f{0.5f, 0.1f * i, 0.2f}, Vec3f{0.5f, 0.1f * i + 0.2f, 0.6f}, Vec3f{0.5f, 0.3f, 0.9f}});
  }
  return triangles;
}

TEST(KdTreeBuild, SweepFindsTheBruteForceBestPlane) {
  for (const KdTreeConfig config : {KdTreeConfig{}, KdTreeConfig{.traversal_cost = 15.0f, .intersection_cost = 20.0f},
                                    KdTreeConfig{.empty_bonus = 1.0f}}) {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      const TriangleSet set = test::set_from_triangles(small_mixed_soup(seed));
      kd::SahNode root = kd::make_root(set);
      const kd::SplitPlane plane = kd::find_best_split(root, config);
      ASSERT_TRUE(std::isfinite(plane.cost));
      EXPECT_EQ(plane.cost, brute_force_best_cost(root, config)) << "seed " << seed;
      // The same at the next level, where the events come from clipped bounds.
      auto [below, above] = kd::split_node(std::move(root), plane, set);
      for (const kd::SahNode* child : {&below, &above}) {
        if (child->size() < 2) continue;
        EXPECT_EQ(kd::find_best_split(*child, config).cost, brute_force_best_cost(*child, config)) << "seed " << seed;
      }
    }
  }
}

TEST(KdTreeBuild, SplitKeepsEveryTriangleWithItsClippedBounds) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(5, 500, 0.05f, 0.5f));
  kd::SahNode root = kd::make_root(set);
  const std::vector<Bounds3f> parent_bounds = bounds_from_events(root);
  const std::vector<std::uint32_t> parent_triangles = root.triangles;
  const kd::SplitPlane plane = kd::find_best_split(root, KdTreeConfig{});
  ASSERT_GE(plane.axis, 0);
  auto [below, above] = kd::split_node(std::move(root), plane, set);

  EXPECT_EQ(below.box.hi[plane.axis], plane.position);
  EXPECT_EQ(above.box.lo[plane.axis], plane.position);
  std::size_t straddlers = 0;
  for (const kd::SahNode* child : {&below, &above}) {
    EXPECT_TRUE(std::is_sorted(child->triangles.begin(), child->triangles.end()));
    for (int axis = 0; axis < 3; ++axis) EXPECT_TRUE(std::is_sorted(child->events[axis].begin(), child->events[axis].end()));
    const std::vector<Bounds3f> child_bounds = bounds_from_events(*child);
    for (std::size_t t = 0; t < child->size(); ++t) {
      const std::uint32_t triangle = child->triangles[t];
      const auto parent_index = static_cast<std::size_t>(
          std::lower_bound(parent_triangles.begin(), parent_triangles.end(), triangle) - parent_triangles.begin());
      const Bounds3f& was = parent_bounds[parent_index];
      const bool crosses = was.lo[plane.axis] < plane.position && was.hi[plane.axis] > plane.position;
      const Bounds3f expected =
          crosses ? kd::intersect_bounds(kd::clipped_triangle_bounds(set.triangles[triangle], child->box), was) : was;
      straddlers += crosses ? 1 : 0;
      EXPECT_EQ(child_bounds[t].lo, expected.lo) << "triangle " << triangle;
      EXPECT_EQ(child_bounds[t].hi, expected.hi) << "triangle " << triangle;
    }
  }
  EXPECT_GT(straddlers, 0u);
  // Every parent triangle is in the child its bounds reach (both when it crosses the plane).
  for (std::size_t t = 0; t < parent_triangles.size(); ++t) {
    const Bounds3f& b = parent_bounds[t];
    const bool in_below = std::binary_search(below.triangles.begin(), below.triangles.end(), parent_triangles[t]);
    const bool in_above = std::binary_search(above.triangles.begin(), above.triangles.end(), parent_triangles[t]);
    const float lo = b.lo[plane.axis], hi = b.hi[plane.axis], p = plane.position;
    const bool in_plane = lo == p && hi == p;
    EXPECT_EQ(in_below, in_plane ? plane.planar_below : lo < p) << "triangle " << parent_triangles[t];
    EXPECT_EQ(in_above, in_plane ? !plane.planar_below : hi > p) << "triangle " << parent_triangles[t];
  }
}

TEST(KdTreeBuild, SplitCostFollowsTheSurfaceAreaHeuristic) {
  const Bounds3f box{{0, 0, 0}, {2, 1, 1}};  // half area 2 + 1 + 2 = 5
  const KdTreeConfig config{.traversal_cost = 1.0f, .intersection_cost = 2.0f, .empty_bonus = 0.8f};
  const kd::SplitCost along_x(box, 0, 6, config), along_x5(box, 0, 5, config);
  // Cut at x = 0.5: below half area 0.5 + 1 + 0.5 = 2, above 1.5 + 1 + 1.5 = 4. Triangles are
  // counted in leaf blocks, rounded up.
  const kd::SplitCost along_x40(box, 0, 40, config);
  EXPECT_DOUBLE_EQ(along_x(0.5f, 3, 5), 1.0 + 2.0 * (2.0 / 5 * 1 + 4.0 / 5 * 1));
  EXPECT_DOUBLE_EQ(along_x40(0.5f, kd::kLeafWidth + 1, 3 * kd::kLeafWidth), 1.0 + 2.0 * (2.0 / 5 * 2 + 4.0 / 5 * 3));
  EXPECT_DOUBLE_EQ(along_x5(0.5f, 0, 5), static_cast<double>(0.8f) * (1.0 + 2.0 * (4.0 / 5 * 1)));
  // A cut at the box face leaving every triangle in a child equal to the box makes no progress.
  EXPECT_EQ(along_x5(0.0f, 0, 5), std::numeric_limits<double>::infinity());
  EXPECT_EQ(kd::SplitCost(box, 1, 5, config)(1.0f, 5, 0), std::numeric_limits<double>::infinity());
  // Planar triangles in the face cut off into a flat cell is progress: below half area 2 * 1.
  EXPECT_DOUBLE_EQ(kd::SplitCost(box, 2, 5, config)(0.0f, 2, 3), 1.0 + 2.0 * (2.0 / 5 * 1 + 1.0 * 1));
  // A box without area cannot be split.
  EXPECT_EQ(kd::SplitCost(Bounds3f{{0, 0, 0}, {1, 0, 0}}, 0, 4, config)(0.5f, 2, 2), std::numeric_limits<double>::infinity());
}

TEST(KdTreeBuild, TreeDoesNotDependOnThreadCount) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(23, 40000, 0.001f, 0.05f));
  const std::vector<Ray> rays = test::random_rays(set, 6, 2000);
  const auto build_and_query = [&](int threads, auto build, AccelStats& stats) {
    const ThreadLimit limit(threads);
    const auto accel = build();
    stats = accel.stats();
    std::vector<Hit> hits;
    for (const Ray& r : rays) hits.push_back(accel.intersect(r));
    return hits;
  };
  const auto check = [&](auto build) {
    AccelStats one{}, two{};
    const auto hits_one = build_and_query(1, build, one);
    const auto hits_two = build_and_query(2, build, two);
    EXPECT_EQ(one.node_count, two.node_count);
    EXPECT_EQ(one.leaf_count, two.leaf_count);
    EXPECT_EQ(one.reference_count, two.reference_count);
    EXPECT_EQ(one.max_depth, two.max_depth);
    EXPECT_EQ(one.memory_bytes, two.memory_bytes);
    for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_TRUE(test::same_bits(hits_one[i], hits_two[i])) << "ray " << i;
  };
  check([&] { return KdTree::build(set); });
  check([&] { return MedianBsp::build(set); });
}

TEST(KdTreeBuild, StatsDescribeTheTree) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(24, 20000, 0.005f, 0.05f));
  const KdTree tree = KdTree::build(set, KdTreeConfig{.traversal_cost = 1.0f});
  const AccelStats& s = tree.stats();
  EXPECT_EQ(s.leaf_count, s.node_count + 1);  // a full binary tree
  EXPECT_GE(s.reference_count, set.size());
  EXPECT_LE(s.reference_count, 4 * set.size());
  EXPECT_GE(s.max_depth, 12);
  EXPECT_LE(s.max_depth, 1 + std::lround(8 + 1.3 * std::log2(static_cast<double>(set.size()))));  // the automatic limit
  EXPECT_GE(s.memory_bytes, set.size() * (9 * sizeof(float) + 2 * sizeof(std::uint32_t)) + s.reference_count * 4);
  EXPECT_EQ(KdTree::name(), "kdtree");

  const MedianBsp bsp = MedianBsp::build(set, MedianBspConfig{.max_depth = 10, .max_leaf_size = 2});
  EXPECT_EQ(bsp.stats().leaf_count, bsp.stats().node_count + 1);
  EXPECT_EQ(bsp.stats().max_depth, 11);  // 20000 triangles never fit 2 per leaf in 2^10 leaves
  EXPECT_EQ(MedianBsp::name(), "median-bsp");
}

TEST(KdTreeBuild, TerminationFollowsTheCosts) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(25, 2000, 0.005f, 0.05f));
  // Traversal far dearer than testing every triangle: the root stays a leaf.
  const KdTree leaf = KdTree::build(set, KdTreeConfig{.traversal_cost = 1e6f});
  EXPECT_EQ(leaf.stats().node_count, 0u);
  EXPECT_EQ(leaf.stats().reference_count, set.size());
  // Cheaper traversal gives a deeper tree; max_depth caps it.
  const KdTree shallow = KdTree::build(set, KdTreeConfig{.traversal_cost = 4.0f});
  const KdTree deep = KdTree::build(set, KdTreeConfig{.traversal_cost = 0.25f});
  EXPECT_LT(shallow.stats().leaf_count, deep.stats().leaf_count);
  EXPECT_EQ(KdTree::build(set, KdTreeConfig{.traversal_cost = 1.0f, .max_depth = 5}).stats().max_depth, 6);
  // Duplicates cannot be separated: the tree stops splitting them.
  const TriangleSet copies = test::set_from_triangles(std::vector<Triangle>(
      1000, Triangle{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0.5f}}));
  EXPECT_LE(KdTree::build(copies).stats().reference_count, 4000u);
}

TEST(KdTreeBuild, RejectsBadConfig) {
  const TriangleSet set = test::set_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}});
  EXPECT_THROW(KdTree::build(set, KdTreeConfig{.traversal_cost = -1.0f}), Error);
  EXPECT_THROW(KdTree::build(set, KdTreeConfig{.intersection_cost = 0.0f}), Error);
  EXPECT_THROW(KdTree::build(set, KdTreeConfig{.empty_bonus = 0.0f}), Error);
  EXPECT_THROW(KdTree::build(set, KdTreeConfig{.empty_bonus = 1.5f}), Error);
  EXPECT_THROW(KdTree::build(set, KdTreeConfig{.max_depth = 65}), Error);
  EXPECT_THROW(KdTree::build(set, KdTreeConfig{.max_depth = -1}), Error);
  EXPECT_THROW(MedianBsp::build(set, MedianBspConfig{.max_depth = 100}), Error);
  EXPECT_THROW(MedianBsp::build(set, MedianBspConfig{.max_leaf_size = 0}), Error);
}

}  // namespace
}  // namespace vf
