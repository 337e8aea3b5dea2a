// KdTree and MedianBsp against the BruteForce oracle on adversarial scenes and rays:
// closest hits must be bit-identical (t, u, v, triangle; ties to the lowest index), occluded() equal.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "unit/kdtree/oracle_check.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/median_bsp.hpp"

namespace vf {
namespace {

using test::Triangle;

/// Origins uniform inside the set's bounds, random directions, finite or unbounded tmax.
std::vector<Ray> inside_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x71u);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    const float tmax = rng.uniform() < 0.5f ? std::numeric_limits<float>::infinity() : rng.uniform();
    r = Ray{test::point_around(rng, set.bounds, 0.0f), test::random_direction(rng), 0.0f, tmax};
  }
  return rays;
}

/// Every ray kind of the differential suite, plus rays with tmin / tmax exactly at (and one ulp
/// around) the hits of the random ones.
std::vector<Ray> adversarial_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  std::vector<Ray> rays = test::random_rays(set, seed, n);
  const BruteForce oracle = BruteForce::build(set);
  std::vector<Hit> hits;
  for (const Ray& r : rays) hits.push_back(oracle.intersect(r));
  std::vector<Ray> boundary = test::boundary_t_rays(rays, hits);
  if (boundary.size() > n) boundary.resize(n);
  for (auto more : {test::axis_parallel_rays(set, seed, n), test::zero_component_rays(set, seed, n),
                    test::surface_origin_rays(set, seed, n), test::grazing_rays(set, seed, n),
                    test::model_rays(set, seed, n), inside_rays(set, seed, n), boundary})
    rays.insert(rays.end(), more.begin(), more.end());
  return rays;
}

/// Unit-cube lattice: in every plane x, y or z = i/n (i = 0..n), n x n axis-aligned quads of two
/// triangles each. Every triangle lies in a candidate split plane and shares edges with others.
std::vector<Triangle> lattice(int n) {
  std::vector<Triangle> out;
  const auto at = [n](int i) { return static_cast<float>(i) / static_cast<float>(n); };
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const auto point = [&](int dj, int dk) {
            Vec3f p;
            p[axis] = at(i);
            p[(axis + 1) % 3] = at(j + dj);
            p[(axis + 2) % 3] = at(k + dk);
            return p;
          };
          out.push_back({point(0, 0), point(1, 0), point(1, 1)});
          out.push_back({point(0, 0), point(1, 1), point(0, 1)});
        }
  return out;
}

/// Rays aimed at the lattice's planes, edges and vertices: origins with coordinates on lattice
/// values, directions along the axes or with a zero component (rays running inside a plane).
std::vector<Ray> lattice_rays(int n, std::uint64_t seed, std::size_t count) {
  Rng rng(seed, 0x1au);
  const auto lattice_value = [&] { return static_cast<float>(rng.next_u32() % (n + 1)) / static_cast<float>(n); };
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    Vec3f org{-0.5f + 2.0f * rng.uniform(), -0.5f + 2.0f * rng.uniform(), -0.5f + 2.0f * rng.uniform()};
    Vec3f dir = test::random_direction(rng);
    const int axis = static_cast<int>(rng.next_u32() % 3);
    switch (rng.next_u32() % 4) {
      case 0:  // along an axis, through a lattice line or vertex
        org[(axis + 1) % 3] = lattice_value();
        if (rng.uniform() < 0.5f) org[(axis + 2) % 3] = lattice_value();
        dir = Vec3f{0.0f};
        dir[axis] = rng.uniform() < 0.5f ? -1.0f : 1.0f;
        break;
      case 1:  // inside a lattice plane
        org[axis] = lattice_value();
        dir[axis] = rng.uniform() < 0.5f ? -0.0f : 0.0f;
        break;
      case 2:  // from a lattice vertex
        org = {lattice_value(), lattice_value(), lattice_value()};
        break;
      default:
        break;
    }
    r = Ray{org, dir};
  }
  return rays;
}

/// The structure with its defaults and with parameters that make a much deeper tree (small leaves,
/// many split planes per triangle), so that both shapes are checked.
template <class A>
std::vector<A> builds(const TriangleSet& set);

template <>
std::vector<KdTree> builds<KdTree>(const TriangleSet& set) {
  std::vector<KdTree> out;
  out.push_back(KdTree::build(set));
  out.push_back(KdTree::build(set, KdTreeConfig{.traversal_cost = 0.1f, .intersection_cost = 1.5f}));
  return out;
}

template <>
std::vector<MedianBsp> builds<MedianBsp>(const TriangleSet& set) {
  std::vector<MedianBsp> out;
  out.push_back(MedianBsp::build(set));
  out.push_back(MedianBsp::build(set, MedianBspConfig{.max_leaf_size = 1}));
  return out;
}

template <class A>
class KdStructureQueries : public ::testing::Test {};

using KdStructures = ::testing::Types<KdTree, MedianBsp>;
TYPED_TEST_SUITE(KdStructureQueries, KdStructures);

TYPED_TEST(KdStructureQueries, RandomSoupsOfSeveralSizes) {
  struct Case {
    std::uint64_t seed;
    std::size_t count;
    float min_size, max_size;
  };
  for (const Case c : {Case{1, 12, 0.05f, 0.5f}, Case{2, 1000, 0.001f, 0.3f}, Case{3, 20000, 1e-4f, 0.02f},
                       Case{4, 400, 0.5f, 4.0f}, Case{5, 3000, 1e-5f, 2.0f}}) {
    const TriangleSet set = test::set_from_triangles(test::random_soup(c.seed, c.count, c.min_size, c.max_size));
    const test::OracleRays oracle(set, adversarial_rays(set, c.seed, 400));
    for (const TypeParam& accel : builds<TypeParam>(set))
      EXPECT_GT(test::expect_matches_oracle(accel, oracle, "soup " + std::to_string(c.seed)), 100u);
  }
}

TYPED_TEST(KdStructureQueries, TrianglesLyingInSplitPlanes) {
  const int n = 4;
  const TriangleSet set = test::set_from_triangles(lattice(n));
  std::vector<Ray> rays = lattice_rays(n, 7, 3000);
  const std::vector<Ray> more = adversarial_rays(set, 8, 300);
  rays.insert(rays.end(), more.begin(), more.end());
  const test::OracleRays oracle(set, std::move(rays));
  const std::vector<TypeParam> accels = builds<TypeParam>(set);
  EXPECT_GT(accels.back().stats().node_count, 10u);  // the deep build splits in the lattice planes
  for (const TypeParam& accel : accels) EXPECT_GT(test::expect_matches_oracle(accel, oracle, "lattice"), 1000u);
}

TYPED_TEST(KdStructureQueries, FlatScenes) {
  // Exactly in the plane z = 0.5, then in a tilted plane.
  const TriangleSet axis_aligned =
      test::set_from_triangles(test::coplanar_soup(9, 500, {0.0f, 0.0f, 0.5f}, {1, 0, 0}, {0, 1, 0}));
  const TriangleSet tilted =
      test::set_from_triangles(test::coplanar_soup(10, 500, {0.1f, 0.2f, 0.3f}, {1, 0.3f, 0.2f}, {0, 1, 0.5f}));
  for (const TriangleSet* set : {&axis_aligned, &tilted}) {
    std::vector<Ray> rays = adversarial_rays(*set, 11, 300);
    Rng rng(12, 0x2u);
    for (int i = 0; i < 500; ++i) {  // straight down onto the plane, and inside it
      const Vec3f p{rng.uniform(), rng.uniform(), 0.5f};
      rays.push_back(Ray{p + Vec3f{0, 0, 1}, {0, 0, -1}});
      rays.push_back(Ray{p, {rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() < 0.5f ? 0.0f : -0.0f}});
    }
    const test::OracleRays oracle(*set, std::move(rays));
    for (const TypeParam& accel : builds<TypeParam>(*set))
      EXPECT_GT(test::expect_matches_oracle(accel, oracle, set == &tilted ? "tilted" : "flat"), 200u);
  }
}

TYPED_TEST(KdStructureQueries, SingleTriangleAndEmptySet) {
  const TypeParam empty = TypeParam::build(TriangleSet{});
  EXPECT_FALSE(empty.intersect(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_FALSE(empty.occluded(Ray{{0, 0, 0}, {0, 0, 1}}));
  EXPECT_EQ(empty.stats().leaf_count, 0u);
  EXPECT_EQ(empty.stats().max_depth, 0);

  const TriangleSet set = test::set_from_triangles({{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}});
  const test::OracleRays oracle(set, adversarial_rays(set, 13, 300));
  for (const TypeParam& one : builds<TypeParam>(set)) {
    const Hit h = one.intersect(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h.t, 2.0f);
    EXPECT_EQ(h.prim, 0u);
    EXPECT_FALSE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, 0.0f, 1.99f}));
    EXPECT_TRUE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, 0.0f, 2.0f}));
    EXPECT_FALSE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, 2.0f, 3.0f}));  // tmin is exclusive
    EXPECT_TRUE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, std::nextafter(2.0f, 0.0f), 2.0f}));
    EXPECT_FALSE(one.occluded(Ray{{0.25f, 0.25f, 2.0f}, {0, 0, -1}, std::nextafter(2.0f, 3.0f), 5.0f}));
    test::expect_matches_oracle(one, oracle, "single");
  }
}

TYPED_TEST(KdStructureQueries, ManyDuplicatesTieToTheLowestIndex) {
  // 300 copies of two triangles above a soup, alternating b, a, b, a, ... then the soup.
  const Triangle a{Vec3f{0.2f, 0.2f, 1.5f}, Vec3f{0.8f, 0.2f, 1.5f}, Vec3f{0.2f, 0.8f, 1.5f}};
  const Triangle b{Vec3f{0.3f, 0.1f, 1.2f}, Vec3f{0.6f, 0.9f, 1.3f}, Vec3f{0.1f, 0.7f, 1.4f}};
  std::vector<Triangle> triangles;
  for (int i = 0; i < 300; ++i) triangles.push_back(i % 2 ? a : b);
  const std::vector<Triangle> soup = test::random_soup(14, 600, 0.01f, 0.2f);
  triangles.insert(triangles.end(), soup.begin(), soup.end());
  const TriangleSet set = test::set_from_triangles(triangles);
  const test::OracleRays oracle(set, adversarial_rays(set, 15, 400));
  for (const TypeParam& accel : builds<TypeParam>(set)) {
    const Hit h = accel.intersect(Ray{{0.3f, 0.3f, 3.0f}, {0, 0, -1}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h.t, 1.5f);
    EXPECT_EQ(h.prim, 1u);  // the first copy of `a`
    test::expect_matches_oracle(accel, oracle, "duplicates");
  }
}

TYPED_TEST(KdStructureQueries, SharedEdgesAndVerticesAreNeverMissed) {
  const int n = 32;
  const TriangleSet set = test::set_from_triangles(test::height_field(16, n));
  std::vector<Ray> rays = adversarial_rays(set, 17, 300);
  Rng rng(18, 0x3u);
  for (int i = 0; i < 1000; ++i) {  // straight down through grid vertices and along grid lines
    const float x = static_cast<float>(rng.next_u32() % (n + 1)) / n;
    const float z = i % 2 ? static_cast<float>(rng.next_u32() % (n + 1)) / n : rng.uniform();
    rays.push_back(Ray{{x, 1.0f, z}, {0, -1, 0}});
  }
  const test::OracleRays oracle(set, std::move(rays));
  for (const TypeParam& accel : builds<TypeParam>(set))
    EXPECT_GT(test::expect_matches_oracle(accel, oracle, "height field"), 1000u);
}

TYPED_TEST(KdStructureQueries, AgreesWithBruteForceBitForBit) {
  // The project's oracle, held to what the headers promise: the same t, u, v, triangle and normal,
  // ties to the lowest index, and the same occlusion.
  const TriangleSet set = test::set_from_triangles(test::random_soup(19, 5000, 0.002f, 0.1f));
  const BruteForce oracle = BruteForce::build(set);
  const std::vector<Ray> rays = adversarial_rays(set, 20, 300);
  for (const TypeParam& accel : builds<TypeParam>(set)) {
    std::size_t hits = 0;
    for (const Ray& ray : rays) {
      const Hit expected = oracle.intersect(ray), got = accel.intersect(ray);
      ASSERT_TRUE(test::same_bits(got, expected)) << "t " << got.t << " vs " << expected.t;
      ASSERT_EQ(accel.occluded(ray), oracle.occluded(ray));
      hits += got ? 1 : 0;
    }
    EXPECT_GT(hits, rays.size() / 10);
  }
}

TEST(MedianBspQueries, RaysThroughCellEdgesFindTheirHits) {
  // The root box is [0, 1]^3 and the first planes are x = 0.5, then y = 0.5 (longest axis, ties to
  // the lowest). Small triangles lie in the cell x, y <= 0.5 with one corner exactly on its edge
  // line x = y = 0.5; rays from the cell x > 0.5, y < 0.5 towards the cell x < 0.5, y > 0.5 pass
  // through that corner, so their interval in the triangle's cell is (nearly) a single point that
  // rounding must not drop.
  std::vector<Triangle> triangles{{Vec3f{0, 0, 0}, Vec3f{0.01f, 0, 0}, Vec3f{0, 0.01f, 0}},
                                  {Vec3f{1, 1, 1}, Vec3f{0.99f, 1, 1}, Vec3f{1, 0.99f, 1}}};
  Rng rng(23, 0xedu);
  for (int i = 0; i < 200; ++i) {
    const Vec3f corner{0.5f, 0.5f, 0.1f + 0.8f * rng.uniform()};
    triangles.push_back({corner, corner - Vec3f{0.01f + 0.05f * rng.uniform(), 0.002f * rng.uniform(), -0.01f},
                         corner - Vec3f{0.002f * rng.uniform(), 0.01f + 0.05f * rng.uniform(), 0.01f}});
  }
  const TriangleSet set = test::set_from_triangles(triangles);
  std::vector<Ray> rays;
  for (int i = 0; i < 4000; ++i) {
    const Vec3f& corner = set.triangles[2 + rng.next_u32() % 200][0];
    const float a = 0.05f + 0.3f * rng.uniform(), b = 0.05f + 0.3f * rng.uniform(), c = 0.1f * (rng.uniform() - 0.5f);
    const Vec3f org = corner + Vec3f{a, -b, c};
    rays.push_back(Ray{org, corner - org});
    rays.push_back(Ray{org, (corner - org) * (0.5f + rng.uniform())});
  }
  const test::OracleRays oracle(set, std::move(rays));
  for (const MedianBspConfig& config : {MedianBspConfig{}, MedianBspConfig{.max_leaf_size = 1}}) {
    const MedianBsp bsp = MedianBsp::build(set, config);
    EXPECT_GT(test::expect_matches_oracle(bsp, oracle, "cell edges"), 1000u);
  }
}

TEST(KdTreeQueries, ExtremeConfigsStayExact) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(21, 3000, 0.001f, 0.3f));
  const test::OracleRays oracle(set, adversarial_rays(set, 22, 200));
  for (const KdTreeConfig& config : {KdTreeConfig{.traversal_cost = 0.0f}, KdTreeConfig{.traversal_cost = 50.0f},
                                     KdTreeConfig{.empty_bonus = 1.0f}, KdTreeConfig{.max_depth = 3}}) {
    const KdTree tree = KdTree::build(set, config);
    test::expect_matches_oracle(tree, oracle, "kdtree config");
  }
  for (const MedianBspConfig& config : {MedianBspConfig{.max_depth = 5}, MedianBspConfig{.max_leaf_size = 1},
                                        MedianBspConfig{.max_depth = 30, .max_leaf_size = 16}}) {
    const MedianBsp bsp = MedianBsp::build(set, config);
    test::expect_matches_oracle(bsp, oracle, "median config");
  }
}

}  // namespace
}  // namespace vf
