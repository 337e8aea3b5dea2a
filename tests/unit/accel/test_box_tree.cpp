// BoxTree's batch query: the rays grouped by item (rays_by_item) are exactly the (item, ray) pairs
// the single-ray query gives (items_met), at each width this build runs, on boxes and rays chosen
// to meet the box test's edge cases (origins on slab planes with zero direction components, rays
// that touch a box at their origin alone, flat and nested boxes, finite and shifted ray intervals,
// intervals that end just before a box or start just after it, so that only their widening lets
// the box in, rays that all share one interval, skipped rays); and the same pairs leaf by leaf
// (visit_leaves), with the rays' own values, where rays a visit settles may leave later leaves.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "visfield/accel/box_tree.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/rng.hpp"

namespace vf {
namespace {

using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;  // (item, ray)

std::vector<Bounds3f> adversarial_boxes(Rng& rng) {
  std::vector<Bounds3f> boxes;
  for (int k = 0; k < 400; ++k) {
    const Vec3f centre{rng.uniform() * 20 - 10, rng.uniform() * 4 - 2, rng.uniform() * 20 - 10};
    Vec3f half{0.1f + rng.uniform(), 0.1f + rng.uniform(), 0.1f + rng.uniform()};
    if (k % 17 == 0) half.y = 0.0f;  // flat boxes
    if (k % 29 == 0) half = half * 6.0f;  // large boxes holding many others
    boxes.push_back({centre - half, centre + half});
  }
  boxes.push_back(Bounds3f{});  // an empty box is never met
  return boxes;
}

std::vector<Ray> adversarial_rays(Rng& rng, const std::vector<Bounds3f>& boxes) {
  std::vector<Ray> rays;
  for (int i = 0; i < 6000; ++i) {
    Ray ray;
    ray.org = {rng.uniform() * 24 - 12, rng.uniform() * 6 - 3, rng.uniform() * 24 - 12};
    ray.dir = {rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1};
    switch (i % 8) {
      case 1:  // a zero direction component, the origin on a box's slab plane on that axis
      {
        const Bounds3f& b = boxes[rng.next_u32() % (boxes.size() - 1)];
        const int axis = static_cast<int>(rng.next_u32() % 3);
        ray.dir[axis] = (i % 12 == 1) ? -0.0f : 0.0f;
        ray.org[axis] = (i % 4 == 1) ? b.lo[axis] : b.hi[axis];
        break;
      }
      case 2:  // a short segment
        ray.tmax = rng.uniform() * 3;
        break;
      case 3:  // an interval that starts away from the origin
        ray.tmin = rng.uniform() * 2;
        ray.tmax = ray.tmin + rng.uniform() * 10;
        break;
      case 4:  // along an axis
        ray.dir = {0.0f, 0.0f, 0.0f};
        ray.dir[static_cast<int>(rng.next_u32() % 3)] = rng.uniform() < 0.5f ? 1.0f : -1.0f;
        break;
      case 5:  // from a point of a box's face, leaving it: the box is met at t = 0 alone
      {
        const Bounds3f& b = boxes[rng.next_u32() % (boxes.size() - 1)];
        const int axis = static_cast<int>(rng.next_u32() % 3);
        for (int a = 0; a < 3; ++a) ray.org[a] = b.lo[a] + (b.hi[a] - b.lo[a]) * rng.uniform();
        const bool high = i % 12 == 5;
        ray.org[axis] = high ? b.hi[axis] : b.lo[axis];
        ray.dir[axis] = high ? 0.5f + rng.uniform() : -0.5f - rng.uniform();
        break;
      }
      case 6:  // an interval that ends a hair before the ray reaches a box: met through its widening alone
      case 7:  // an interval that starts a hair after the ray leaves a box: the same
      {
        const Bounds3f& b = boxes[rng.next_u32() % (boxes.size() - 1)];
        ray.dir = b.center() - ray.org;
        double entry = 0.0, exit = std::numeric_limits<double>::infinity();
        int entry_axis = 0, exit_axis = 0;
        for (int a = 0; a < 3; ++a) {
          const double t0 = (static_cast<double>(b.lo[a]) - ray.org[a]) / ray.dir[a], t1 = (static_cast<double>(b.hi[a]) - ray.org[a]) / ray.dir[a];
          if (std::min(t0, t1) > entry) entry = std::min(t0, t1), entry_axis = a;
          if (std::max(t0, t1) < exit) exit = std::max(t0, t1), exit_axis = a;
        }
        // The tree's boxes are grown by 2^-16 of their largest extent (x times 2^-16 of the
        // distance, in t), the far end of the box test by 2^-16 more, and the interval by 2^-16 of
        // itself: a hair of 2^-16 (x + 3/2) misses the grown box unless the interval is widened.
        const double extent = std::max({b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z});
        if (i % 8 == 6 && entry > 0.0 && entry < exit) {
          const double x = extent / (std::fabs(ray.dir[entry_axis]) * entry);
          ray.tmax = static_cast<float>(entry * (1.0 - 0x1p-16 * (x + 1.5)));
        }
        if (i % 8 == 7 && exit > 0.0 && entry < exit) {
          const double x = extent / (std::fabs(ray.dir[exit_axis]) * exit);
          ray.tmin = static_cast<float>(exit * (1.0 + 0x1p-16 * (x + 1.5)));
        }
        break;
      }
      default:
        break;
    }
    rays.push_back(ray);
  }
  return rays;
}

Pairs one_ray_at_a_time(const BoxTree& tree, const std::vector<Ray>& rays, const std::vector<std::uint8_t>& skip) {
  Pairs pairs;
  std::vector<std::uint32_t> items;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (skip[i]) continue;
    items.clear();
    tree.items_met(rays[i], items);
    for (const std::uint32_t item : items) pairs.emplace_back(item, static_cast<std::uint32_t>(i));
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

Pairs grouped(const BoxTree& tree, const std::vector<Ray>& rays, const std::vector<std::uint8_t>& skip, int width, ItemRays& out) {
  tree.rays_by_item(rays, skip.data(), out, width);
  Pairs pairs;
  std::set<std::uint32_t> items;
  for (const ItemRays::List& list : out.lists) {
    EXPECT_TRUE(items.insert(list.item).second) << "item " << list.item << " has two lists";
    EXPECT_GT(list.count, 0u);
    const std::uint32_t* ray = out.rays.data() + list.begin;
    EXPECT_TRUE(std::is_sorted(ray, ray + list.count)) << "item " << list.item << ": rays out of order";
    for (std::uint32_t k = 0; k < list.count; ++k) pairs.emplace_back(list.item, ray[k]);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

/// A tree over the adversarial boxes with `leaf_items` a leaf, its adversarial rays with every fifth
/// skipped, and the same rays with one interval for every open ray (the columns' batch carries tmin
/// and tmax as constants then; a skipped ray's own interval does not count).
struct TreeCase {
  std::vector<Bounds3f> boxes;
  BoxTree tree;
  std::vector<Ray> rays, same_interval;
  std::vector<std::uint8_t> skip;

  TreeCase(std::uint64_t seed, int leaf_items) {
    Rng rng(seed);
    boxes = adversarial_boxes(rng);
    tree = BoxTree::build(boxes, leaf_items);
    rays = adversarial_rays(rng, boxes);
    skip.assign(rays.size(), 0);
    for (std::size_t i = 0; i < rays.size(); i += 5) skip[i] = 1;
    same_interval = rays;
    for (std::size_t i = 0; i < same_interval.size(); ++i) {
      same_interval[i].tmin = skip[i] ? 0.5f : 0.125f;
      same_interval[i].tmax = skip[i] ? 1.0f : 4.0f;
    }
  }
};

class BoxTreeLeaves : public ::testing::TestWithParam<int> {};

TEST_P(BoxTreeLeaves, RaysByItemArePairsOfTheSingleRayQueryAtEveryWidth) {
  TreeCase c(41, GetParam());
  const BoxTree& tree = c.tree;
  const std::vector<Ray>& rays = c.rays;
  const std::vector<std::uint8_t>& skip = c.skip;
  const Pairs expected = one_ray_at_a_time(tree, rays, skip);
  ASSERT_GT(expected.size(), rays.size());  // rays meet several boxes each: the grouping is exercised
  const std::vector<Ray>& same_interval = c.same_interval;
  const Pairs expected_same = one_ray_at_a_time(tree, same_interval, skip);
  std::set<int> widths{BoxTree::batch_width(1), BoxTree::batch_width(8), BoxTree::batch_width(16)};
  for (const int width : widths) {
    ItemRays out;
    EXPECT_EQ(grouped(tree, rays, skip, width, out), expected) << "width " << width;
    EXPECT_EQ(grouped(tree, same_interval, skip, width, out), expected_same) << "width " << width << ", one interval";
    // The buffers are reused: a second, smaller call gives its own pairs, nothing of the first.
    const std::vector<Ray> fewer(rays.begin(), rays.begin() + 777);
    const std::vector<std::uint8_t> none(fewer.size(), 0);
    EXPECT_EQ(grouped(tree, fewer, none, width, out), one_ray_at_a_time(tree, fewer, none)) << "width " << width;
    // A leaf's items share one list of rays, side by side: lists with one begin have one count.
    grouped(tree, rays, skip, width, out);
    std::map<std::uint32_t, std::uint32_t> count_at;
    for (const ItemRays::List& list : out.lists) {
      const auto place = count_at.emplace(list.begin, list.count).first;
      EXPECT_EQ(place->second, list.count) << "width " << width;
    }
    if (GetParam() == 1) {
      EXPECT_EQ(count_at.size(), out.lists.size()) << "width " << width;
    } else {
      EXPECT_LT(count_at.size(), out.lists.size()) << "width " << width;  // some leaves hold several items
    }
  }
}

/// visit_leaves()'s (item, ray) pairs, each leaf's rays checked against `rays` bit for bit, in
/// ascending order, its items each in one leaf.
Pairs visited(const BoxTree& tree, const std::vector<Ray>& rays, std::vector<std::uint8_t>& skip, int width,
              const std::function<void(const BoxTree::LeafRays&)>& also = {}) {
  Pairs pairs;
  std::set<std::uint32_t> items;
  tree.visit_leaves(rays, skip.data(), [&](const BoxTree::LeafRays& leaf) {
    EXPECT_GT(leaf.count, 0u);
    EXPECT_TRUE(std::is_sorted(leaf.ids, leaf.ids + leaf.count)) << "rays out of order";
    for (std::size_t k = 0; k < leaf.count; ++k) {
      const Ray& ray = rays[leaf.ids[k]];
      const float want[8] = {ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z, ray.tmin, ray.tmax};
      for (int c = 0; c < 8; ++c)
        ASSERT_EQ(std::bit_cast<std::uint32_t>(leaf.columns[c][k]), std::bit_cast<std::uint32_t>(want[c])) << "ray " << leaf.ids[k] << " column " << c;
    }
    for (const std::uint32_t item : leaf.items) {
      EXPECT_TRUE(items.insert(item).second) << "item " << item << " in two leaves";
      for (std::size_t k = 0; k < leaf.count; ++k) pairs.emplace_back(item, leaf.ids[k]);
    }
    if (also) also(leaf);
  }, width);
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

TEST_P(BoxTreeLeaves, VisitedLeavesArePairsOfTheSingleRayQueryWithTheRaysThemselves) {
  TreeCase c(43, GetParam());
  const Pairs expected = one_ray_at_a_time(c.tree, c.rays, c.skip);
  const Pairs expected_same = one_ray_at_a_time(c.tree, c.same_interval, c.skip);
  ASSERT_GT(expected.size(), c.rays.size());
  std::set<int> widths{BoxTree::batch_width(1), BoxTree::batch_width(8), BoxTree::batch_width(16)};
  for (const int width : widths) {
    EXPECT_EQ(visited(c.tree, c.rays, c.skip, width), expected) << "width " << width;
    EXPECT_EQ(visited(c.tree, c.same_interval, c.skip, width), expected_same) << "width " << width << ", one interval";
  }
}

TEST_P(BoxTreeLeaves, RaysSettledByAVisitAreLeftOutOfLaterLeavesOnly) {
  Rng rng(47);
  const std::vector<Bounds3f> boxes = adversarial_boxes(rng);
  const BoxTree tree = BoxTree::build(boxes, GetParam());
  const std::vector<Ray> rays = adversarial_rays(rng, boxes);
  const std::vector<std::uint8_t> none(rays.size(), 0);
  const Pairs expected = one_ray_at_a_time(tree, rays, none);
  std::set<int> widths{BoxTree::batch_width(1), BoxTree::batch_width(8), BoxTree::batch_width(16)};
  for (const int width : widths) {
    // The first leaf settles every third ray: later leaves may leave those out, and only those.
    std::vector<std::uint8_t> skip(rays.size(), 0);
    std::set<std::pair<std::uint32_t, std::uint32_t>> first_leaf;
    bool first = true;
    const Pairs got = visited(tree, rays, skip, width, [&](const BoxTree::LeafRays& leaf) {
      if (!first) return;
      first = false;
      for (const std::uint32_t item : leaf.items)
        for (std::size_t k = 0; k < leaf.count; ++k) first_leaf.emplace(item, leaf.ids[k]);
      for (std::size_t i = 0; i < rays.size(); i += 3) skip[i] = 1;
    });
    std::size_t left_out = 0;
    for (const auto& pair : expected) {
      const bool present = std::binary_search(got.begin(), got.end(), pair);
      if (pair.second % 3 != 0 || first_leaf.count(pair)) {
        EXPECT_TRUE(present) << "width " << width << ": item " << pair.first << " ray " << pair.second;
      } else {
        left_out += present ? 0 : 1;
      }
    }
    EXPECT_TRUE(std::includes(expected.begin(), expected.end(), got.begin(), got.end())) << "width " << width;
    if (width > 1) {
      EXPECT_GT(left_out, 0u) << "width " << width << ": the walk never looked at the settled rays";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(ItemsALeaf, BoxTreeLeaves, ::testing::Values(1, 4));

TEST(BoxTreeVisits, OnLanesTheLeavesNearestTheRaysComeFirst) {
  if (BoxTree::batch_width() == 1) GTEST_SKIP() << "this build walks a ray at a time (leaves in tree order)";
  // A row of 64 boxes along x; rays from just beyond one end of the row along it, fanned out a little:
  // the first leaf visited holds the box at that end, and from leaf to leaf the boxes only move away.
  // From one of the two ends that is against the tree's own order, whichever way the builder laid it.
  std::vector<Bounds3f> boxes;
  for (int k = 0; k < 64; ++k) {
    const float x = 2.0f * static_cast<float>(k);
    boxes.push_back({Vec3f{x, -0.5f, -0.5f}, Vec3f{x + 1.0f, 0.5f, 0.5f}});
  }
  const BoxTree tree = BoxTree::build(boxes);
  for (const int width : std::set<int>{BoxTree::batch_width(8), BoxTree::batch_width(16)})
    for (const float side : {-1.0f, 1.0f}) {
      const float start = side < 0.0f ? -1.0f : 128.0f;  // just before box 0, or just after box 63
      Rng rng(5);
      std::vector<Ray> rays;
      for (int i = 0; i < 512; ++i)
        rays.push_back(Ray{Vec3f{start, 0.0f, 0.0f}, Vec3f{-side, (rng.uniform() - 0.5f) * 0.02f, (rng.uniform() - 0.5f) * 0.02f}});
      std::vector<float> distance;  // each visited leaf's box, from the rays' origin
      tree.visit_leaves(rays, nullptr, [&](const BoxTree::LeafRays& leaf) {
        ASSERT_EQ(leaf.items.size(), 1u);
        const Bounds3f& box = boxes[leaf.items[0]];
        distance.push_back(std::max(box.lo.x - start, start - box.hi.x));
      }, width);
      ASSERT_EQ(distance.size(), 64u) << "width " << width << ", from side " << side;
      EXPECT_EQ(distance.front(), 1.0f) << "width " << width << ", from side " << side;
      EXPECT_TRUE(std::is_sorted(distance.begin(), distance.end())) << "width " << width << ", from side " << side;
    }
}

TEST(BoxTree, RefusesLeavesOfNoItemOrTooMany) {
  const std::vector<Bounds3f> boxes{Bounds3f{Vec3f{0.0f}, Vec3f{1.0f}}};
  EXPECT_THROW(BoxTree::build(boxes, 0), Error);
  EXPECT_THROW(BoxTree::build(boxes, 129), Error);
  EXPECT_NO_THROW(BoxTree::build(boxes, 128));
}

TEST(BoxTree, RaysByItemOfNoRaysOrNoBoxesIsEmpty) {
  Rng rng(7);
  const std::vector<Bounds3f> boxes = adversarial_boxes(rng);
  const std::vector<Ray> rays = adversarial_rays(rng, boxes);
  ItemRays out;
  const std::vector<std::uint8_t> all(rays.size(), 1);
  BoxTree::build(boxes).rays_by_item(rays, all.data(), out);
  EXPECT_TRUE(out.lists.empty());
  BoxTree::build(std::vector<Bounds3f>{}).rays_by_item(rays, nullptr, out);
  EXPECT_TRUE(out.lists.empty());
}

}  // namespace
}  // namespace vf
